// The drag study (seed 003 Fig. 4.19: "the drag force (divided by diameter D) on the
// obstacle", against the stream velocity U, slip and no-slip): one run measures the mean
// drag of its obstacle over the stats rows after study.transient (the flow developing
// past the obstacle), with the block-average error of block_average() (blocks of
// ⌈20 τ_int⌉ rows, τ_int the drag series' integrated autocorrelation time; study.hpp). The
// sweep is one run per U, independent processes (`--set system.U=…`), and one plot of
// their study.csv rows:
//   grainflow plot --rows out/drag_*/study.csv --x U --y drag_per_D --y-err drag_per_D_err
//                  --group obstacle_kind --points
// stats.csv's drag_x is the whole force (momentum per unit time the disks give the
// obstacle over each row's window); the study divides by D. The seed's error bars are
// standard deviations; these are standard errors of the mean drag.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/error.hpp"
#include "engine/ed/circular_obstacle.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"
#include "scenes/src/studies/study.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {
namespace {

// Optional (default: one pass of the stream through the box, Lx / U).
inline constexpr Key<double> transient{"study.transient"};

class Drag final : public Study {
public:
  explicit Drag(const StudyContext& c)
      : rows_("drag", c.stats_columns, {"drag_x", "drag_y"}),
        U_(c.scene.get(ed_keys::U)),
        D_(c.scene.get(ed_keys::obstacle_D)),
        // The surface at the end of the run (a phase may switch it).
        kind_(ed_keys::obstacle_kind_at(c.scene, c.scene.count(ed_keys::phase) - 1)),
        transient_(c.scene.find(transient).value_or(c.scene.get(ed_keys::box)[0] / c.scene.get(ed_keys::U))) {}
  void stats(double time, std::span<const double> row) override { rows_.add(time, row); }
  void save(io::ArchiveWriter& w) const override { rows_.save(w); }
  void load(io::ArchiveReader& r) override { rows_.load(r); }

  StudyResult result() const override {
    const auto& t = rows_.time();
    const std::size_t n = t.size();
    const std::size_t first = rows_.first_row_after(
        transient_, 16, "study.transient", "a longer run.until, a smaller output.stats_every or study.transient");
    std::vector<double> fx(n - first), fy(n - first);
    for (std::size_t i = first; i < n; ++i) {
      fx[i - first] = rows_.column("drag_x")[i] / D_;
      fy[i - first] = rows_.column("drag_y")[i] / D_;
    }
    const BlockAverage drag = block_average(fx), lift = block_average(fy);
    const double dt = n > 1 ? t[1] - t[0] : 0.0;  // the rows' spacing (output.stats_every)

    StudyResult res;
    res.values = {
        {"U", U_, kNoError, "σ/τ", "stream velocity (system.U)"},
        {"D", D_, kNoError, "σ", "obstacle diameter"},
        {"obstacle_kind", double(int(obstacle_boundary(kind_))), kNoError, "",
         "the obstacle's surface: 0 slip, 1 noslip_thermal, 2 noslip_flip (boundary.obstacle.kind)"},
        {"drag_per_D", drag.mean, drag.error, "E/σ²",
         "mean drag_x / D after study.transient; error: block averages (blocks of ⌈20 τ_int⌉ rows)"},
        {"lift_per_D", lift.mean, lift.error, "E/σ²", "mean drag_y / D (0 for a symmetric flow), as drag_per_D"},
        {"tau_int", drag.tau_int * dt, kNoError, "τ", "integrated autocorrelation time of the drag rows"},
        {"block_length", double(drag.block_rows) * dt, kNoError, "τ", "length of one block"},
        {"blocks", double(drag.blocks), kNoError, "", "blocks the error is taken from"},
        {"measured_span", t.back() - (first > 0 ? t[first - 1] : t[0] - dt), kNoError, "τ",
         "simulated time the mean covers (after study.transient)"},
    };
    char detail[200];
    std::snprintf(detail, sizeof detail, "%zu blocks of %zu rows; 20 τ_int = %.1f rows", drag.blocks, drag.block_rows,
                  20 * drag.tau_int);
    res.checks.push_back({"blocks at least 20 τ_int long, at least 8 of them (else the error is likely low)",
                          drag.long_enough, detail});
    if (!drag.long_enough)
      res.notes.push_back("the run is shorter than 8 blocks of 20 τ_int: the blocks are correlated and the error "
                          "understates the uncertainty (a longer run.until)");

    auto& f = res.figure;
    char title[200];
    std::snprintf(title, sizeof title, "Drag on the obstacle (%s), U = %g, D = %g: F/D = %.4g ± %.2g", kind_.c_str(), U_,
                  D_, drag.mean, drag.error);
    f.title = title;
    f.x = {"t (τ)", false, {}};
    f.y = {"drag_x / D (E/σ²)", false, {}};
    render::plot::Series rows, mean, lo, hi;
    rows.label = "drag_x / D (each stats window)";
    for (std::size_t i = 0; i < n; ++i) {
      rows.x.push_back(t[i] - 0.5 * dt);
      rows.y.push_back(rows_.column("drag_x")[i] / D_);
    }
    const double x0 = t[first] - dt, x1 = t.back();
    mean.label = "mean after study.transient";
    mean.colour = render::Rgb{0.1f, 0.1f, 0.1f};
    mean.width_px = 1.5f;
    mean.x = {x0, x1};
    mean.y = {drag.mean, drag.mean};
    lo.label = "± one standard error (block averages)";
    lo.dashed = hi.dashed = true;
    lo.colour = hi.colour = render::Rgb{0.5f, 0.5f, 0.5f};
    lo.width_px = hi.width_px = 1.25f;
    lo.x = hi.x = {x0, x1};
    const double e = std::isfinite(drag.error) ? drag.error : 0.0;
    lo.y = {drag.mean - e, drag.mean - e};
    hi.y = {drag.mean + e, drag.mean + e};
    f.series = {rows, mean, lo, hi};
    return res;
  }

private:
  StatsRows rows_;
  double U_, D_;
  std::string kind_;
  double transient_;
};

void declare(Schema& s) {
  s.table("study")
      .add_float(transient, 0.0, "drag: stats rows up to this time are the developing flow, not the mean (default: "
                                 "one pass of the stream through the box, Lx / U)", "τ")
      .at_least(0.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(study_keys::study)) return;
    const bool mine = sc.get(study_keys::kind) == "drag";
    if (sc.has(transient) && !mine)
      c.fail(transient.path, "is a key of the drag study; this scene's study is " + sc.get(study_keys::kind));
    if (!mine) return;
    if (!sc.has(ed_keys::obstacle))
      c.fail(study_keys::kind.path, "the drag study measures the drag on the obstacle; allowed: with [boundary.obstacle]");
    if (!(sc.get(ed_keys::U) > 0.0))
      c.fail(ed_keys::U.path, "the drag study needs a stream past the obstacle; allowed: system.U > 0");
  });
}

std::unique_ptr<Study> open(const StudyContext& c) { return std::make_unique<Drag>(c); }

}  // namespace

StudyEntry drag_study() {
  return {"drag", "mean drag on the obstacle / D with block-average errors; a sweep of runs over U gives Fig. 4.19 "
                  "(seed 003 §4.2)",
          "ed", &declare, &open};
}

}  // namespace grainflow::scenes
