// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Settings objects as Python classes: one typed property per setting over an engine settings
// struct, so a setting's name, default (the struct's member initialiser), range and check (the
// struct's validate()) are the engine's, defined once. A property refuses a value of the wrong
// type with a TypeError naming the setting, and a value the engine's check refuses with
// InvalidArgumentError (the engine's message names it); the object is unchanged then. Enum
// settings take a member or its name ('multigrid'). Keyword arguments become property
// assignments (applyKeywords). A SettingTable lists the settings of one engine struct once, for
// every class that shows them (FluidSettings and Simulation both show FluidParams').
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/format.h"
#include "common/range.h"
#include "python/convert.h"

namespace hf::python {

namespace py = pybind11;

// An enum setting from a member of its Python enum or from the member's name.
template <class E>
E enumArg(const py::handle& value, const std::string& name) {
  // The enum's Python class, from a value of it (pybind11 3's py::type::of<E> takes classes only).
  const py::object type = py::type::of(py::cast(E{}));
  if (py::isinstance<py::str>(value)) {
    const py::dict members = type.attr("__members__");
    if (members.contains(value)) return members[value].template cast<E>();
  } else if (py::isinstance(value, type)) {
    return value.template cast<E>();
  }
  std::string allowed;
  for (const auto& item : py::dict(type.attr("__members__"))) {
    allowed += (allowed.empty() ? "'" : ", '") + item.first.cast<std::string>() + "'";
  }
  throw InvalidArgument(name + " must be one of " + allowed + " (or hapticfluid." +
                        type.attr("__name__").cast<std::string>() + ".<name>), got " + py::repr(value).cast<std::string>());
}

// A value of the setting's type T: an enum by member or name; a number or a flag as itself (True
// is no number, 1 no flag: both are refused naming the setting); the rest by pybind11's casters.
template <class T>
T settingArg(const py::handle& value, const std::string& name) {
  if constexpr (std::is_enum_v<T>) {
    return enumArg<T>(value, name);
  } else {
    if constexpr (std::is_arithmetic_v<T>) {
      const std::string type = Py_TYPE(value.ptr())->tp_name;  // numpy's flag: numpy.bool_ (numpy.bool in 2.x)
      const bool is_flag = py::isinstance<py::bool_>(value) || type == "numpy.bool_" || type == "numpy.bool";
      if (is_flag != std::is_same_v<T, bool>) throw py::type_error(wrongType<T>(value, name));
    }
    return castArg<T>(value, name.c_str());
  }
}

// One setting of an engine struct P as Python shows it: name, docstring, range (when it has
// one), its value read from P, and a Python value written into P (converted, naming the setting
// by the qualified name given).
template <class P>
struct Setting {
  std::string name;
  std::string doc;
  std::optional<Range> range;
  std::function<py::object(const P&)> get;
  std::function<void(P&, const py::handle&, const std::string&)> set;
};

// The settings of P, listed once.
template <class P>
class SettingTable {
 public:
  // A setting of Python type T read by get(const P&) -> T and written by set(P&, T).
  template <class T, class Get, class Set>
  SettingTable& add(const char* name, Get get, Set set, const char* doc, std::optional<Range> range = std::nullopt) {
    rows_.push_back(Setting<P>{name, doc, range,
                               [get](const P& p) -> py::object {
                                 auto v = get(p);
                                 if constexpr (std::is_base_of_v<py::handle, decltype(v)>) {
                                   return py::reinterpret_steal<py::object>(v.release());
                                 } else {
                                   return py::cast(std::move(v));
                                 }
                               },
                               [set](P& p, const py::handle& value, const std::string& qualified) {
                                 set(p, settingArg<T>(value, qualified));
                               }});
    return *this;
  }
  const std::vector<Setting<P>>& rows() const { return rows_; }

 private:
  std::vector<Setting<P>> rows_;
};

// The engine's check of a whole settings struct S, as its SettingsClass registered it.
template <class S>
std::function<void(const S&)>& settingsCheck() {
  static std::function<void(const S&)> check;
  return check;
}

// While one of these lives (keywords being applied), the properties leave the whole-struct check
// to the end: settings that bound each other, such as min_sim_dt <= max_sim_dt, may come in any
// order. Scopes nest; the GIL serialises every use.
class DeferredChecks {
 public:
  DeferredChecks() { ++depth(); }
  ~DeferredChecks() { --depth(); }
  DeferredChecks(const DeferredChecks&) = delete;
  DeferredChecks& operator=(const DeferredChecks&) = delete;
  static bool active() { return depth() > 0; }

 private:
  static int& depth() {
    static int d = 0;
    return d;
  }
};

// settings.<key> = value for every keyword; an unknown key is a TypeError naming it and the
// settings that exist. `who` names the call in the message ("Simulation").
inline void applyKeywords(py::object& settings, const py::kwargs& kwargs, const char* who) {
  if (!kwargs) return;
  const py::list names = settings.attr("fields")();
  for (const auto& item : kwargs) {
    if (!names.contains(item.first)) {
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n.cast<std::string>();
      throw py::type_error(std::string(who) + "() got an unexpected keyword argument '" +
                           item.first.cast<std::string>() + "'; the settings are: " + all);
    }
    py::setattr(settings, item.first, item.second);
  }
}

// The settings a constructor uses: a copy of `settings` (or the defaults when None) with the
// keywords applied. A `settings` of another type is a TypeError naming it.
template <class S>
S settingsWithKeywords(const py::object& settings, const py::kwargs& kwargs, const char* who) {
  const py::object type = py::type::of<S>();
  if (!settings.is_none() && !py::isinstance(settings, type)) {
    throw py::type_error(std::string(who) + ": settings must be a hapticfluid." +
                         type.attr("__name__").cast<std::string>() + " or None, got " +
                         py::str(py::type::handle_of(settings).attr("__name__")).cast<std::string>());
  }
  py::object copy = settings.is_none() ? py::cast(S{}) : settings.attr("copy")();
  {
    const DeferredChecks deferred;
    applyKeywords(copy, kwargs, who);
  }
  S result = copy.cast<S>();
  if (settingsCheck<S>()) settingsCheck<S>()(result);
  return result;
}

// repr() with a float32 setting by its shortest decimal (0.08, not 0.07999999821186066).
inline std::string shortRepr(const py::handle& v) {
  if (py::isinstance<py::float_>(v)) {
    return py::repr(py::float_(std::stod(py::str("{:.7g}").format(v).cast<std::string>()))).cast<std::string>();
  }
  if (py::isinstance<py::tuple>(v)) {
    std::string r = "(";
    for (const auto& item : py::tuple(py::reinterpret_borrow<py::object>(v))) r += (r.size() > 1 ? ", " : "") + shortRepr(item);
    return r + ")";
  }
  return py::repr(v).cast<std::string>();
}

template <class S>
class SettingsClass {
 public:
  // check: the engine's validation of the whole struct (throws InvalidArgument naming the field).
  SettingsClass(py::module_& m, const char* name, const char* doc, std::function<void(const S&)> check)
      : cls_(m, name, doc), name_(name), check_(std::move(check)) {
    settingsCheck<S>() = check_;
  }

  // A setting of Python type T read by get(const S&) -> T and written by set(S&, T).
  template <class T, class Get, class Set>
  SettingsClass& field(const char* name, Get get, Set set, const char* doc) {
    SettingTable<S> one;
    one.template add<T>(name, get, set, doc);
    return fields(one);
  }

  // The settings of a table of S.
  SettingsClass& fields(const SettingTable<S>& table) {
    for (const Setting<S>& row : table.rows()) add(row);
    return *this;
  }

  // The settings of a table of the part of S at `member` (SimulationConfig::params).
  template <class P>
  SettingsClass& fields(const SettingTable<P>& table, P S::*member) {
    for (const Setting<P>& row : table.rows()) {
      add(Setting<S>{row.name, row.doc, row.range, [get = row.get, member](const S& s) { return get(s.*member); },
                     [set = row.set, member](S& s, const py::handle& value, const std::string& qualified) {
                       set(s.*member, value, qualified);
                     }});
    }
    return *this;
  }

  // Finishes the class: S(**settings) (the engine's defaults with those set), fields() (the
  // names, in order), limits(), to_dict(), copy(), ==, repr. Returns it.
  py::class_<S>& done() {
    const std::vector<std::string> names = names_;
    const std::string cls = name_;
    cls_.def(py::init([cls](const py::kwargs& kw) { return settingsWithKeywords<S>(py::none(), kw, cls.c_str()); }),
             "The engine's defaults, with the settings given as keywords.");
    cls_.def_static("fields", [names]() { return names; }, "The settings' names, in order.");
    const std::vector<std::pair<std::string, Range>> ranges = ranges_;
    cls_.def_static(
        "limits",
        [ranges]() {
          py::dict d;
          for (const auto& [name, r] : ranges) {
            // (the engine's float32 bounds by their shortest decimal: 0.001, not 0.0010000000474974513)
            d[py::str(name)] = py::dict(py::arg("min") = std::stod(num(r.min)), py::arg("max") = std::stod(num(r.max)),
                                        py::arg("max_exclusive") = r.max_exclusive);
          }
          return d;
        },
        "The range of each numeric setting that has one, as the engine checks it: {name: {'min', 'max',\n"
        "'max_exclusive'}} (max itself refused when max_exclusive).");
    cls_.def("to_dict", [names](const py::object& self) {
          py::dict d;
          for (const auto& n : names) d[py::str(n)] = self.attr(n.c_str());
          return d;
        }, "Every setting by name.");
    cls_.def("copy", [](const S& s) { return S(s); }, "An independent copy.");
    cls_.def("__copy__", [](const S& s) { return S(s); });
    cls_.def("__deepcopy__", [](const S& s, const py::object&) { return S(s); }, py::arg("memo"));
    cls_.def("__eq__", [](const py::object& a, const py::object& b) {
      return py::isinstance(b, py::type::of(a)) && a.attr("to_dict")().equal(b.attr("to_dict")());
    });
    cls_.def("__repr__", [names, cls](const py::object& self) {
      std::string r = cls + "(";
      for (std::size_t i = 0; i < names.size(); ++i) {
        r += (i ? ", " : "") + names[i] + "=" + shortRepr(self.attr(names[i].c_str()));
      }
      return r + ")";
    });
    return cls_;
  }

 private:
  void add(Setting<S> row) {
    const std::string qualified = name_ + "." + row.name;
    auto check = check_;
    cls_.def_property(
        row.name.c_str(), [get = row.get](const S& s) { return get(s); },
        [set = row.set, check, qualified](S& s, const py::object& value) {
          S candidate = s;
          set(candidate, value, qualified);
          if (check && !DeferredChecks::active()) check(candidate);
          s = std::move(candidate);
        },
        row.doc.c_str());
    names_.push_back(row.name);
    if (row.range) ranges_.emplace_back(row.name, *row.range);
  }

  py::class_<S> cls_;
  std::string name_;
  std::function<void(const S&)> check_;
  std::vector<std::string> names_;
  std::vector<std::pair<std::string, Range>> ranges_;
};

}  // namespace hf::python
