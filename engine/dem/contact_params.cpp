#include "engine/dem/contact_params.hpp"

#include <array>
#include <cstdio>

#include "engine/core/error.hpp"

namespace grainflow::dem {

namespace {

// Each row provides the interface of its family (sub_model.hpp).
static_assert([]<class... M>(TypeList<M...>) { return (NormalModel<M> && ...); }(NormalModels{}));
static_assert([]<class... M>(TypeList<M...>) { return (TangentialModel<M> && ...); }(TangentialModels{}));
static_assert([]<class... M>(TypeList<M...>) { return (CohesionModel<M> && ...); }(CohesionModels{}));
static_assert(std::is_trivially_copyable_v<ContactParams> && std::is_trivially_copyable_v<ContactModelSpec>,
              "checkpoints store both as bytes");

template <class... M>
constexpr std::array<SubModelInfo, sizeof...(M)> infos(TypeList<M...>) {
  return {SubModelInfo{M::kName, M::kDescription}...};
}
template <class Kind>
constexpr auto kInfos = infos(typename Kind::Models{});

// A name picks one row: names within a family are distinct.
template <class Kind>
constexpr bool distinct_names() {
  const auto& t = kInfos<Kind>;
  for (std::size_t a = 0; a < t.size(); ++a)
    for (std::size_t b = a + 1; b < t.size(); ++b)
      if (t[a].name == t[b].name) return false;
  return true;
}
static_assert(distinct_names<NormalKind>() && distinct_names<TangentialKind>() && distinct_names<CohesionKind>(),
              "two rows of one table share a name");

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

template <class Kind>
std::string allowed_names() {
  std::string s;
  for (const SubModelInfo& m : kInfos<Kind>) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

template <class A, class B>
void require_combinable(std::string_view fa, std::string_view fb) {
  if constexpr (!combinable<A, B>())
    throw Error("dem: the " + std::string(fa) + " \"" + std::string(A::kName) + "\" cannot be combined with the " +
                std::string(fb) + " \"" + std::string(B::kName) + "\"");
}

}  // namespace

void CoeffCheck::require(bool ok, const char* key, double value, const char* allowed) const {
  if (!ok) throw Error("dem: " + where + "." + key + " = " + num(value) + " is not allowed; " + allowed);
}

template <class Kind>
std::span<const SubModelInfo> sub_models() {
  return kInfos<Kind>;
}

template <class Kind>
std::vector<std::string> model_names() {
  std::vector<std::string> v;
  for (const SubModelInfo& m : kInfos<Kind>) v.emplace_back(m.name);
  return v;
}

template <class Kind>
Kind kind_from_name(std::string_view name) {
  for (std::size_t r = 0; r < kInfos<Kind>.size(); ++r)
    if (kInfos<Kind>[r].name == name) return Kind{static_cast<int>(r)};
  throw Error("dem: " + std::string(Kind::kFamily) + " \"" + std::string(name) + "\" is unknown; allowed: " +
              allowed_names<Kind>());
}

template <class Kind>
void require_known(Kind k) {
  if (k.row < 0 || static_cast<std::size_t>(k.row) >= Kind::Models::size)
    throw Error("dem: " + std::string(Kind::kFamily) + " number " + std::to_string(k.row) +
                " is unknown (a corrupt checkpoint?); allowed: " + allowed_names<Kind>());
}

#define GRAINFLOW_DEM_KIND_API(Kind)                                    \
  template std::span<const SubModelInfo> sub_models<Kind>();            \
  template std::vector<std::string> model_names<Kind>();                \
  template Kind kind_from_name<Kind>(std::string_view);                 \
  template void require_known<Kind>(Kind);
GRAINFLOW_DEM_KIND_API(NormalKind)
GRAINFLOW_DEM_KIND_API(TangentialKind)
GRAINFLOW_DEM_KIND_API(CohesionKind)
#undef GRAINFLOW_DEM_KIND_API

void require_composable(const ContactModelSpec& spec) {
  visit_model(spec.normal, [&]<class N>(std::type_identity<N>) {
    visit_model(spec.tangential, [&]<class T>(std::type_identity<T>) {
      visit_model(spec.cohesion, [&]<class C>(std::type_identity<C>) {
        require_combinable<N, T>(NormalKind::kFamily, TangentialKind::kFamily);
        require_combinable<N, C>(NormalKind::kFamily, CohesionKind::kFamily);
        require_combinable<T, C>(TangentialKind::kFamily, CohesionKind::kFamily);
      });
    });
  });
}

void validate(const ContactParams& p, const ContactModelSpec& spec, const std::string& where) {
  require_composable(spec);
  const CoeffCheck check{where};
  visit_model(spec.normal, [&]<class M>(std::type_identity<M>) { M::validate(p, check); });
  visit_model(spec.tangential, [&]<class M>(std::type_identity<M>) { M::validate(p, check); });
  visit_model(spec.cohesion, [&]<class M>(std::type_identity<M>) { M::validate(p, check); });
}

ContactParams mix(const ContactParams& a, const ContactParams& b) {
  ContactParams c;
  [&]<class... B>(TypeList<B...>) {
    ((static_cast<B&>(c) = B::mix(a, b)), ...);
  }(ContactCoeffs{});
  return c;
}

}  // namespace grainflow::dem
