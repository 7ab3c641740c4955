// Contact parameters of one particle group (or one pair of groups) and the choice of
// sub-models a contact law is composed from (seed 000 §2.4, ch. 5), both assembled from
// the tables of contact_models.hpp, with name look-up, checks and mixing. SI units.
#pragma once
#include <concepts>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "engine/dem/contact_models.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

namespace detail {
// The types of the lists after Acc, each once, in order of first appearance.
template <class Acc, class... Lists>
struct UnionOf {
  using type = Acc;
};
template <class... A, class B0, class... B, class... Lists>
struct UnionOf<TypeList<A...>, TypeList<B0, B...>, Lists...>
    : UnionOf<std::conditional_t<(std::is_same_v<A, B0> || ...), TypeList<A...>, TypeList<A..., B0>>, TypeList<B...>,
              Lists...> {};
template <class... A, class... Lists>
struct UnionOf<TypeList<A...>, TypeList<>, Lists...> : UnionOf<TypeList<A...>, Lists...> {};

template <class... N, class... T, class... C>
typename UnionOf<TypeList<>, typename N::Reads..., typename T::Reads..., typename C::Reads...>::type coeffs_of(
    TypeList<N...>, TypeList<T...>, TypeList<C...>);

template <class L>
struct InheritAll;
template <class... B>
struct InheritAll<TypeList<B...>> : B... {};
}  // namespace detail

// Every coefficient block that some row of the tables reads, each once, in table order.
using ContactCoeffs = decltype(detail::coeffs_of(NormalModels{}, TangentialModels{}, CohesionModels{}));

// Contact parameters: the fields of all blocks of ContactCoeffs (k1, e, gamma_n, kt, mu,
// …), each declared once, in sub_model.hpp or its sub-model's header, next to its range
// check and mixing rule. Trivially copyable: checkpoints store it as bytes.
struct ContactParams : detail::InheritAll<ContactCoeffs> {};

// A row of one table: which sub-model of the family is chosen. Checkpoints store the row.
// The named rows are for C++ callers; scenes pick a sub-model by its name.
struct NormalKind {
  using Models = NormalModels;
  static constexpr std::string_view kFamily = "normal contact model";
  int row = 0;
  bool operator==(const NormalKind&) const = default;
  static const NormalKind Walton, Hooke;
};
struct TangentialKind {
  using Models = TangentialModels;
  static constexpr std::string_view kFamily = "tangential contact model";
  int row = 0;
  bool operator==(const TangentialKind&) const = default;
  static const TangentialKind Walton, History, None;
};
struct CohesionKind {
  using Models = CohesionModels;
  static constexpr std::string_view kFamily = "cohesion model";
  int row = 0;
  bool operator==(const CohesionKind&) const = default;
  static const CohesionKind None, VanDerWaals;
};

namespace detail {
template <class M, class... Ms>
constexpr int row_of(TypeList<Ms...>) {
  const bool same[] = {std::is_same_v<M, Ms>...};
  for (int r = 0; r < int(sizeof...(Ms)); ++r)
    if (same[r]) return r;
  return -1;
}
}  // namespace detail

// The row of sub-model M in Kind's table.
template <class Kind, class M>
constexpr Kind kind_of() {
  constexpr int row = detail::row_of<M>(typename Kind::Models{});
  static_assert(row >= 0, "not a row of this family's table (contact_models.hpp)");
  return Kind{row};
}

inline constexpr NormalKind NormalKind::Walton = kind_of<NormalKind, WaltonNormal>();
inline constexpr NormalKind NormalKind::Hooke = kind_of<NormalKind, HookeNormal>();
inline constexpr TangentialKind TangentialKind::Walton = kind_of<TangentialKind, WaltonTangential>();
inline constexpr TangentialKind TangentialKind::History = kind_of<TangentialKind, HistoryTangential>();
inline constexpr TangentialKind TangentialKind::None = kind_of<TangentialKind, NoTangential>();
inline constexpr CohesionKind CohesionKind::None = kind_of<CohesionKind, NoCohesion>();
inline constexpr CohesionKind CohesionKind::VanDerWaals = kind_of<CohesionKind, VdwCohesion>();

// Which sub-models make up the contact law; one law per simulation, parameters per
// group pair.
struct ContactModelSpec {
  NormalKind normal = NormalKind::Walton;
  TangentialKind tangential = TangentialKind::Walton;
  CohesionKind cohesion = CohesionKind::None;
};

// What the sub-model headers must provide (sub_model.hpp); contact_params.cpp checks each
// row, so that a sub-model missing a piece is named at compile time.
template <class M>
concept SubModel = requires(const ContactParams& p, const CoeffCheck& c, double m) {
  { M::kName } -> std::convertible_to<std::string_view>;
  { M::kDescription } -> std::convertible_to<std::string_view>;
  typename M::Reads;
  typename M::Params;
  { M::kHistory } -> std::convertible_to<int>;
  M::validate(p, c);
  { M::make(p, m) } -> std::same_as<typename M::Params>;
};
template <class M>
concept NormalModel = SubModel<M> && requires(const ContactParams& p, double m) {
  { M::kNeedsMass } -> std::convertible_to<bool>;
  { M::collision_time(p, m, m) } -> std::same_as<double>;
  { M::max_stiffness(p) } -> std::same_as<double>;
};
template <class M>
concept TangentialModel = SubModel<M> && requires(const ContactParams& p) {
  { M::kNeedsMass } -> std::convertible_to<bool>;
  { M::stiffness(p) } -> std::same_as<double>;
};
template <class M>
concept CohesionModel = SubModel<M> && requires(const typename M::Params& q) {
  { M::kNeedsRadius } -> std::convertible_to<bool>;
  { M::range(q) } -> std::same_as<double>;
};

// Name and one-line description of each row, in table order (the scene schema's enum).
struct SubModelInfo {
  std::string_view name;
  std::string_view description;
};
template <class Kind>
std::span<const SubModelInfo> sub_models();
template <class Kind>
std::vector<std::string> model_names();
// Throws grainflow::Error listing the allowed names when `name` is no row's.
template <class Kind>
Kind kind_from_name(std::string_view name);
// Throws grainflow::Error for a row outside the table (a corrupt checkpoint).
template <class Kind>
void require_known(Kind k);
template <class Kind>
std::string_view model_name(Kind k) {
  require_known(k);
  return sub_models<Kind>()[static_cast<std::size_t>(k.row)].name;
}

inline NormalKind normal_kind_from_name(std::string_view name) { return kind_from_name<NormalKind>(name); }
inline TangentialKind tangential_kind_from_name(std::string_view name) { return kind_from_name<TangentialKind>(name); }
inline CohesionKind cohesion_kind_from_name(std::string_view name) { return kind_from_name<CohesionKind>(name); }
inline std::vector<std::string> normal_model_names() { return model_names<NormalKind>(); }
inline std::vector<std::string> tangential_model_names() { return model_names<TangentialKind>(); }
inline std::vector<std::string> cohesion_model_names() { return model_names<CohesionKind>(); }

namespace detail {
template <class F, class M0, class... Ms>
decltype(auto) visit_row(std::size_t row, F& f) {
  if constexpr (sizeof...(Ms) > 0) {
    if (row != 0) return visit_row<F, Ms...>(row - 1, f);
  }
  return f(std::type_identity<M0>{});
}
template <class F, class... M>
decltype(auto) visit_list(TypeList<M...>, std::size_t row, F& f) {
  return visit_row<F, M...>(row, f);
}
}  // namespace detail

// f(std::type_identity<M>{}) for the sub-model M chosen by k: the one step from a run-time
// choice to the compile-time sub-model, for every family (throws for an unknown row).
template <class Kind, class F>
decltype(auto) visit_model(Kind k, F&& f) {
  require_known(k);
  return detail::visit_list(typename Kind::Models{}, static_cast<std::size_t>(k.row), f);
}

namespace detail {
template <class X, class Y>
constexpr bool accepts() {
  if constexpr (requires { X::template kCombinesWith<Y>; }) return bool(X::template kCombinesWith<Y>);
  else return true;
}
}  // namespace detail
// Whether two sub-models (of different families) may be composed: false when either
// declares `template <class Other> static constexpr bool kCombinesWith` false for the other.
template <class A, class B>
constexpr bool combinable() {
  return detail::accepts<A, B>() && detail::accepts<B, A>();
}
template <class N, class T, class C>
constexpr bool kComposable = combinable<N, T>() && combinable<N, C>() && combinable<T, C>();
// Throws grainflow::Error naming the first pair of the chosen sub-models that cannot be
// composed, or an unknown row.
void require_composable(const ContactModelSpec& spec);

// Throws grainflow::Error naming `where` (e.g. "groups[0].contact") when a value is
// outside its allowed range for the chosen sub-models, or when they cannot be composed.
void validate(const ContactParams& p, const ContactModelSpec& spec, const std::string& where);

// The contact law between unlike groups: each coefficient block's mixing rule (arithmetic
// means; derived damping rates stay derived; damp_flag only when both have it).
ContactParams mix(const ContactParams& a, const ContactParams& b);

}  // namespace grainflow::dem
