#pragma once
// The list of constraint types, in the order the solver projects them within
// one iteration (Gauss-Seidel over types, then over elements). Adding a type:
// define it (see constraints.hpp), add it here, add its Desc and validation in
// scene.hpp / compile.cpp.
#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "xpbd/constraints.hpp"

namespace xpbd {

// Order: stretch, then bending and volume, then contact-like inequalities
// (so they have the last word within an iteration), then pins.
using ConstraintTypes =
    std::tuple<Distance, DihedralBending, IsometricBending, TetVolume, GlobalVolume, Collision,
               Wall, Penetration, Tether, Pin>;

// True for the types projected element by element by the generic
// project_all (fixed kArity, p[], eval()). GlobalVolume has variable arity
// and its own kernel, solve_global_volumes() (special_constraints.hpp).
template <class T>
inline constexpr bool is_generic_constraint_v = !std::is_same_v<T, GlobalVolume>;

inline constexpr std::size_t kNumConstraintTypes = std::tuple_size_v<ConstraintTypes>;

namespace detail {
template <class T, class Tuple>
struct TupleIndex;
template <class T, class... Ts>
struct TupleIndex<T, std::tuple<Ts...>> {
  static constexpr std::size_t value = [] {
    constexpr bool same[] = {std::is_same_v<T, Ts>...};
    for (std::size_t i = 0; i < sizeof...(Ts); ++i)
      if (same[i]) return i;
    return sizeof...(Ts);
  }();
  static_assert(value < sizeof...(Ts), "type is not in ConstraintTypes");
};
template <class Tuple>
struct ArraysOf;
template <class... Ts>
struct ArraysOf<std::tuple<Ts...>> {
  using type = std::tuple<std::vector<Ts>...>;
};
}  // namespace detail

// Position of T in ConstraintTypes.
template <class T>
inline constexpr std::size_t type_index_v = detail::TupleIndex<T, ConstraintTypes>::value;

// One flat std::vector per constraint type.
using ConstraintArrays = detail::ArraysOf<ConstraintTypes>::type;

// Calls f(std::type_identity<T>{}) for every constraint type T, in solve order.
template <class F>
constexpr void for_each_constraint_type(F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::type_identity<std::tuple_element_t<I, ConstraintTypes>>{}), ...);
  }(std::make_index_sequence<kNumConstraintTypes>{});
}

}  // namespace xpbd
