// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Functions whose arguments are converted by the binding itself, naming the one of the wrong
// type. pybind11 answers a call that matches no signature with "incompatible function arguments"
// and every signature, naming no argument. defNamed(c, "set_probe", f, py::arg("centre"), ...)
// binds f as c.def would, but takes each typed argument as Named<T>: its caster (pybind11's own
// for T) converts the value and keeps what went wrong instead of refusing the call, and the
// function then raises
//   TypeError: Simulation.set_probe(): centre must be 3 numbers (x, y, z), got str 'abc'
// before f runs. The signature pybind11 writes is T's, so help() and the stub read as before.
// py::object, py::handle, py::args and py::kwargs arguments pass as they are (f converts them,
// naming them: castArg, settingArg). A name is bound once: Named arguments take every value, so a
// second overload of the name would never be tried.
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "python/convert.h"

namespace hf::python {

namespace py = pybind11;

// A typed argument as loaded: pybind11's caster for T holding the value, or what was wrong.
template <class T>
struct Named {
  py::detail::make_caster<T> caster;
  bool ok = false;
  std::string problem;  // "must be 3 numbers (x, y, z), got str 'abc'"
};

// Arguments that pass through unconverted.
template <class A>
inline constexpr bool kPassThrough =
    std::is_same_v<py::detail::intrinsic_t<A>, py::object> || std::is_same_v<py::detail::intrinsic_t<A>, py::handle> ||
    std::is_same_v<py::detail::intrinsic_t<A>, py::args> || std::is_same_v<py::detail::intrinsic_t<A>, py::kwargs>;

template <class A>
using Taken = std::conditional_t<kPassThrough<A>, A, Named<A>&>;

namespace detail {

// The names given by py::arg / py::arg_v among a def's extras, in order.
template <class... Extra>
std::vector<std::string> argNames(const Extra&... extra) {
  std::vector<std::string> names;
  auto one = [&names](const auto& e) {
    if constexpr (std::is_base_of_v<py::arg, std::decay_t<decltype(e)>>) names.emplace_back(e.name ? e.name : "");
  };
  (one(extra), ...);
  return names;
}

struct CallInfo {
  std::string qualname;            // "Simulation.set_probe"
  std::vector<std::string> names;  // the arguments', self excluded
  std::string name(std::size_t i) const {
    return i < names.size() && !names[i].empty() ? names[i] : "argument " + std::to_string(i + 1);
  }
};

template <class A, class W>
void check(std::string& problem, W& taken, const CallInfo& info, std::size_t i) {
  if constexpr (!kPassThrough<A>) {
    if (problem.empty() && !taken.ok) problem = info.name(i) + " " + taken.problem;
  }
}

template <class A, class W>
decltype(auto) unwrap(W&& taken) {
  if constexpr (kPassThrough<A>) {
    return std::forward<W>(taken);
  } else {
    return py::detail::cast_op<A>(std::move(taken.caster));
  }
}

template <class F>
struct Signature : Signature<decltype(&F::operator())> {};
template <class R, class... A>
struct Signature<R (*)(A...)> {
  using Return = R;
  template <template <class...> class Make>
  using Apply = Make<R, A...>;
};
template <class C, class R, class... A>
struct Signature<R (C::*)(A...)> : Signature<R (*)(A...)> {};
template <class C, class R, class... A>
struct Signature<R (C::*)(A...) const> : Signature<R (*)(A...)> {};
template <class C, class R, class... A>
struct Signature<R (C::*)(A...) noexcept> : Signature<R (*)(A...)> {};
template <class C, class R, class... A>
struct Signature<R (C::*)(A...) const noexcept> : Signature<R (*)(A...)> {};

// f(args...) with every argument taken by Taken<A>.
template <class... T>
struct Wrap;
template <class R, class... A>
struct Wrap<R, A...> {
  template <class F, std::size_t... I>
  static auto make(F f, std::shared_ptr<const CallInfo> info, std::index_sequence<I...>) {
    return [f = std::move(f), info](Taken<A>... taken) -> R {
      std::string problem;
      (check<A>(problem, taken, *info, I), ...);
      if (!problem.empty()) throw py::type_error(info->qualname + "(): " + problem);
      return f(unwrap<A>(std::forward<Taken<A>>(taken))...);
    };
  }
  template <class F>
  static auto function(F f, std::shared_ptr<const CallInfo> info) {
    return make(std::move(f), std::move(info), std::index_sequence_for<A...>{});
  }
};

// A method f(self, args...): self passes as it is, the rest by Taken<A>.
template <class... T>
struct WrapMethod;
template <class R, class Self, class... A>
struct WrapMethod<R, Self, A...> {
  template <class F, std::size_t... I>
  static auto make(F f, std::shared_ptr<const CallInfo> info, std::index_sequence<I...>) {
    return [f = std::move(f), info](Self self, Taken<A>... taken) -> R {
      std::string problem;
      (check<A>(problem, taken, *info, I), ...);
      if (!problem.empty()) throw py::type_error(info->qualname + "(): " + problem);
      return f(std::forward<Self>(self), unwrap<A>(std::forward<Taken<A>>(taken))...);
    };
  }
  template <class F>
  static auto function(F f, std::shared_ptr<const CallInfo> info) {
    return make(std::move(f), std::move(info), std::index_sequence_for<A...>{});
  }
};

// A member function pointer as a callable taking the bound class's object first; a callable as it is.
template <class T, class C, class R, class... A>
auto methodOf(R (C::*f)(A...)) {
  return [f](T& self, A... a) -> R { return (self.*f)(std::forward<A>(a)...); };
}
template <class T, class C, class R, class... A>
auto methodOf(R (C::*f)(A...) const) {
  return [f](const T& self, A... a) -> R { return (self.*f)(std::forward<A>(a)...); };
}
template <class T, class F>
auto methodOf(F f) {
  return f;
}

}  // namespace detail

// c.def(name, f, extra...) with f's typed arguments named when their type is wrong.
template <class T, class... Options, class F, class... Extra>
py::class_<T, Options...>& defNamed(py::class_<T, Options...>& c, const char* name, F f, const Extra&... extra) {
  const std::string qualname = py::str(c.attr("__name__")).template cast<std::string>() + "." + name;
  auto info = std::make_shared<const detail::CallInfo>(detail::CallInfo{qualname, detail::argNames(extra...)});
  auto method = detail::methodOf<T>(std::move(f));
  using S = detail::Signature<decltype(method)>;
  return c.def(name, S::template Apply<detail::WrapMethod>::function(std::move(method), std::move(info)), extra...);
}

// m.def(name, f, extra...) with f's typed arguments named when their type is wrong.
template <class F, class... Extra>
py::module_& defNamed(py::module_& m, const char* name, F f, const Extra&... extra) {
  auto info = std::make_shared<const detail::CallInfo>(detail::CallInfo{name, detail::argNames(extra...)});
  using S = detail::Signature<F>;
  return m.def(name, S::template Apply<detail::Wrap>::function(std::move(f), std::move(info)), extra...);
}

// c.def(py::init(factory), extra...) with the factory's typed arguments named when their type is wrong.
template <class T, class... Options, class F, class... Extra>
py::class_<T, Options...>& defInitNamed(py::class_<T, Options...>& c, F factory, const Extra&... extra) {
  auto info = std::make_shared<const detail::CallInfo>(
      detail::CallInfo{py::str(c.attr("__name__")).template cast<std::string>(), detail::argNames(extra...)});
  using S = detail::Signature<F>;
  return c.def(py::init(S::template Apply<detail::Wrap>::function(std::move(factory), std::move(info))), extra...);
}

}  // namespace hf::python

namespace pybind11::detail {

// Named<T>: T's own caster does the loading; a value it refuses (or None for a bound class taken
// by reference or holder) is kept as a problem to report by name, so the call goes ahead.
template <class T>
struct type_caster<hf::python::Named<T>> {
  hf::python::Named<T> value;
  static constexpr auto name = make_caster<T>::name;

  bool load(handle src, bool convert) {
    constexpr bool none_refused = std::is_base_of_v<type_caster_generic, make_caster<T>> && !std::is_pointer_v<T>;
    value.ok = !(none_refused && src.is_none()) && value.caster.load(src, convert);
    if (!value.ok) value.problem = "must be " + hf::python::expected<T>() + ", got " + hf::python::shown(src);
    return true;
  }
  template <class U>
  using cast_op_type = hf::python::Named<T>&;
  operator hf::python::Named<T>&() { return value; }
  static handle cast(const hf::python::Named<T>&, return_value_policy, handle) { return none().release(); }
};

}  // namespace pybind11::detail
