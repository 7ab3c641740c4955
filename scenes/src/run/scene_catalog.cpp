#include "scenes/src/run/scene_catalog.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "engine/core/error.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/run/render_keys.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {
namespace {

// The sections every scene has; `colour_attributes` are what render.color_by may take.
void declare_common(Schema& s, std::vector<std::string> colour_attributes) {
  const std::vector<std::string> names = engine_names();
  run_keys::declare(s, names);
  sample_keys::declare(s);
  render_keys::declare(s, std::move(colour_attributes));
  declare_output_keys(s);
  loop_keys::declare(s);
}

class AppCatalog final : public SchemaCatalog {
public:
  AppCatalog() {
    // Before run.engine is known, render.color_by may take any engine's attribute.
    std::vector<std::string> any;
    std::set<std::string> seen;
    for (const auto& e : engines())
      for (auto& a : e.colour_attributes())
        if (seen.insert(a).second) any.push_back(a);
    declare_common(common_, std::move(any));
    for (const auto& e : engines()) {
      auto s = std::make_unique<Schema>();
      declare_common(*s, e.colour_attributes());
      e.declare_keys(*s);
      declare_study_keys(*s, e.name);  // [study] where some study reads this engine's stats
      for (const auto& t : s->tables())
        if (!common_.find_table(t.path()) && t.path().find('.') == std::string::npos &&
            !seen_section(t.path()))
          sections_.push_back(t.path());
      by_engine_.emplace(std::string(e.name), std::move(s));
    }
  }
  const Schema& common() const override { return common_; }
  const Schema* for_engine(std::string_view engine) const override {
    auto it = by_engine_.find(engine);
    return it == by_engine_.end() ? nullptr : it->second.get();
  }
  std::span<const std::string> engine_sections() const override { return sections_; }

private:
  bool seen_section(const std::string& name) const {
    for (const auto& s : sections_)
      if (s == name) return true;
    return false;
  }
  Schema common_;
  std::map<std::string, std::unique_ptr<Schema>, std::less<>> by_engine_;
  std::vector<std::string> sections_;  // top-level sections only engines declare
};

}  // namespace

const SchemaCatalog& scene_catalog() {
  static const AppCatalog catalog;
  return catalog;
}

const Schema& schema_for_engine(std::string_view engine) {
  if (const Schema* s = scene_catalog().for_engine(engine)) return *s;
  throw Error("unknown engine '" + std::string(engine) + "'");
}

Scene load_scene(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  return load_scene(path, overrides, scene_catalog());
}

Scene parse_scene(std::string_view toml_text, std::string_view source_name, const std::vector<std::string>& overrides) {
  return parse_scene(toml_text, source_name, overrides, scene_catalog());
}

}  // namespace grainflow::scenes
