// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Settings objects as Python classes: one typed property per setting over an engine settings
// struct, so a setting's name, default (the struct's member initialiser) and check (the struct's
// validate()) are the engine's, defined once. A property refuses a value of the wrong type with a
// TypeError naming the setting, and a value the engine's check refuses with InvalidArgumentError
// (the engine's message names it); the object is unchanged then. Enum settings take a member or
// its name ('multigrid'). Keyword arguments become property assignments (applyKeywords).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
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

// A value of the setting's type T (an enum by member or name, the rest by pybind11's casters).
template <class T>
T settingArg(const py::handle& value, const std::string& name) {
  if constexpr (std::is_enum_v<T>) {
    return enumArg<T>(value, name);
  } else {
    return castArg<T>(value, name.c_str());
  }
}

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
    const std::string qualified = name_ + "." + name;
    auto check = check_;
    cls_.def_property(
        name, [get](const S& s) { return get(s); },
        [set, check, qualified](S& s, const py::object& value) {
          S candidate = s;
          set(candidate, settingArg<T>(value, qualified));
          if (check && !DeferredChecks::active()) check(candidate);
          s = std::move(candidate);
        },
        doc);
    names_.emplace_back(name);
    return *this;
  }

  // Finishes the class: S(**settings) (the engine's defaults with those set), fields() (the
  // names, in order), to_dict(), copy(), ==, repr. Returns it.
  py::class_<S>& done() {
    const std::vector<std::string> names = names_;
    const std::string cls = name_;
    cls_.def(py::init([cls](const py::kwargs& kw) { return settingsWithKeywords<S>(py::none(), kw, cls.c_str()); }),
             "The engine's defaults, with the settings given as keywords.");
    cls_.def_static("fields", [names]() { return names; }, "The settings' names, in order.");
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
  py::class_<S> cls_;
  std::string name_;
  std::function<void(const S&)> check_;
  std::vector<std::string> names_;
};

}  // namespace hf::python
