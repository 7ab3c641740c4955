#include "scenes/src/studies/study_table.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/atomic_file.hpp"
#include "render/output/png_io.hpp"
#include "scenes/src/outputs/json_writer.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

// Each study's row, defined in its own file in this folder.
StudyEntry haff_cooling_study();
StudyEntry thermostat_hold_study();
StudyEntry sound_speed_study();
StudyEntry couette_study();
StudyEntry drag_study();

std::span<const StudyEntry> studies() {
  static const std::array<StudyEntry, 5> table = {haff_cooling_study(), thermostat_hold_study(), sound_speed_study(),
                                                  couette_study(), drag_study()};
  return table;
}

namespace {

const StudyEntry* find_study(std::string_view name) {
  for (const auto& s : studies())
    if (s.name == name) return &s;
  return nullptr;
}

// study.json, written in one piece (io::AtomicFile).
void write_json(const std::filesystem::path& path, std::string_view kind, const RunRecord& record,
                const StudyResult& r) {
  JsonWriter w;
  w.begin_object();
  w.key("study").value(kind);
  w.key("run_status").value(run_status_name(record.status));
  w.key("sim_time").value(record.sim_time);
  w.key("values").begin_object();
  for (const auto& v : r.values) {
    w.key(v.name).begin_object();
    w.key("value").value(v.value);
    w.key("error").value(v.error);  // null when there is none
    w.key("unit").value(v.unit);
    w.key("doc").value(v.doc);
    w.end_object();
  }
  w.end_object();
  w.key("checks").begin_array();
  for (const auto& c : r.checks) {
    w.begin_object();
    w.key("name").value(c.name);
    w.key("passed").value(c.passed);
    w.key("detail").value(c.detail);
    w.end_object();
  }
  w.end_array();
  w.key("notes").begin_array();
  for (const auto& n : r.notes) w.value(n);
  w.end_array();
  w.end_object();
  io::AtomicFile file(path);
  {
    std::ofstream out(file.path(), std::ios::binary);
    out << w.str() << '\n';
    out.flush();
    if (!out) throw Error("cannot write " + path.string());
  }
  file.commit();
}

// study.csv: the values as one row (NAME, NAME_err), so that the study.csv files of a sweep
// are the rows of one table (`grainflow plot --rows`).
void write_csv(const std::filesystem::path& path, const StudyResult& r) {
  std::string header, row;
  for (const auto& v : r.values) {
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on the
    // temporaries of `"," + std::string`.
    if (!header.empty()) header += ',';
    header.append(v.name).append(",").append(v.name).append("_err");
    if (!row.empty()) row += ',';
    row.append(json_number(v.value)).append(",");
    row.append(std::isfinite(v.error) ? json_number(v.error) : std::string("nan"));
  }
  for (std::string* s : {&row})
    for (std::size_t p = s->find("null"); p != std::string::npos; p = s->find("null")) s->replace(p, 4, "nan");
  io::AtomicFile file(path);
  {
    std::ofstream out(file.path(), std::ios::binary);
    out << header << '\n' << row << '\n';
    out.flush();
    if (!out) throw Error("cannot write " + path.string());
  }
  file.commit();
}

class StudyOutput final : public RunOutput {
public:
  StudyOutput(const StudyEntry& entry, std::unique_ptr<Study> study, std::filesystem::path dir, render::GlContext& gl)
      : entry_(entry), study_(std::move(study)), dir_(std::move(dir)), gl_(gl) {}
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag("study");
    study_->save(w);
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("study");
    study_->load(r);
  }
  void frame(std::int64_t index, const render::Snapshot& s) override { study_->frame(index, s); }
  void stats(double time, std::span<const double> row) override { study_->stats(time, row); }
  void finish(const RunRecord& record) override {
    const StudyResult r = study_->result();
    write_json(dir_ / "study.json", entry_.name, record, r);
    write_csv(dir_ / "study.csv", r);
    render::write_png(dir_ / "study.png", render::plot::draw_figure(gl_, r.figure), {6, true});
    std::printf("study %.*s: %s\n", int(entry_.name.size()), entry_.name.data(), (dir_ / "study.json").c_str());
    for (const auto& v : r.values) {
      if (std::isfinite(v.error)) std::printf("  %-26s %.6g ± %.2g %s\n", v.name.c_str(), v.value, v.error, v.unit.c_str());
      else std::printf("  %-26s %.6g %s\n", v.name.c_str(), v.value, v.unit.c_str());
    }
    for (const auto& c : r.checks) std::printf("  [%s] %s: %s\n", c.passed ? "pass" : "FAIL", c.name.c_str(), c.detail.c_str());
  }

private:
  const StudyEntry& entry_;
  std::unique_ptr<Study> study_;
  std::filesystem::path dir_;
  render::GlContext& gl_;
};

}  // namespace

void declare_study_keys(Schema& s, std::string_view engine) {
  std::vector<std::string> names;
  std::string list;
  for (const auto& st : studies()) {
    if (st.engine != engine) continue;
    names.emplace_back(st.name);
    list += std::string(list.empty() ? "" : "; ") + std::string(st.name) + ": " + std::string(st.description);
  }
  if (names.empty()) return;
  auto& t = s.optional_table(study_keys::study, "a measurement the run makes of itself: writes study.json (results "
                                                "with uncertainties), study.csv and study.png into the run folder");
  t.add_enum(study_keys::kind, names, names.front(), list);
  for (const auto& st : studies())
    if (st.engine == engine) st.declare_keys(s);
}

std::unique_ptr<RunOutput> open_study_output(const OutputContext& c, render::GlContext& gl) {
  if (!c.scene.has(study_keys::study)) return nullptr;
  const StudyEntry* entry = find_study(c.scene.get(study_keys::kind));
  if (!entry) throw Error("unknown study '" + c.scene.get(study_keys::kind) + "'");  // validation refused it already
  std::vector<std::string> columns;
  for (const auto& col : c.stats_columns) columns.push_back(col.name);
  auto study = entry->open(StudyContext{c.scene, std::move(columns)});
  c.claim("study.json");
  c.claim("study.csv");
  c.claim("study.png");
  return std::make_unique<StudyOutput>(*entry, std::move(study), c.dir, gl);
}

StatsRows::StatsRows(std::string_view study, const std::vector<std::string>& columns, std::vector<std::string> wanted)
    : study_(study), wanted_(std::move(wanted)), values_(wanted_.size()) {
  for (const auto& w : wanted_) {
    std::size_t i = 0;
    while (i < columns.size() && columns[i] != w) ++i;
    if (i == columns.size())
      throw Error("the " + std::string(study) + " study needs the stats column '" + w +
                  "', which this run does not write (is the agent that adds it attached?)");
    index_.push_back(i);
  }
}

void StatsRows::add(double time, std::span<const double> row) {
  time_.push_back(time);
  for (std::size_t k = 0; k < index_.size(); ++k) values_[k].push_back(row[index_[k]]);
}

const std::vector<double>& StatsRows::column(std::string_view name) const {
  for (std::size_t k = 0; k < wanted_.size(); ++k)
    if (wanted_[k] == name) return values_[k];
  throw std::logic_error("StatsRows: column '" + std::string(name) + "' was not asked for");
}

std::size_t StatsRows::first_row_after(double start, std::size_t need, std::string_view key,
                                       std::string_view remedy) const {
  const std::size_t n = time_.size();
  std::size_t first = 0;
  // A row stamped at start itself (to round-off) still belongs to the transient.
  while (first < n && time_[first] <= start + 1e-9 * std::max(1.0, start)) ++first;
  if (n - first < need)
    throw Error(study_ + " study: " + std::to_string(n - first) + " stats rows after " + std::string(key) + " = " +
                std::to_string(start) + "; it needs at least " + std::to_string(need) + " (" + std::string(remedy) +
                ")");
  return first;
}

void StatsRows::save(io::ArchiveWriter& w) const {
  w.tag("stats_rows");
  w.array(time_);
  for (const auto& v : values_) w.array(v);
}

void StatsRows::load(io::ArchiveReader& r) {
  r.tag("stats_rows");
  r.array(time_);
  for (auto& v : values_) r.array_of(v, time_.size(), "a study's stats column");
}

MeanError block_mean(std::span<const double> x, int blocks) {
  MeanError m;
  if (x.empty()) return {std::nan(""), kNoError};
  double sum = 0;
  for (double v : x) sum += v;
  m.mean = sum / double(x.size());
  const std::size_t per = x.size() / std::size_t(std::max(blocks, 2));
  if (per == 0) return m;
  std::vector<double> means;
  for (std::size_t b = 0; b + 1 <= x.size() / per && int(means.size()) < blocks; ++b) {
    double s = 0;
    for (std::size_t i = b * per; i < (b + 1) * per; ++i) s += x[i];
    means.push_back(s / double(per));
  }
  if (means.size() < 2) return m;
  double mb = 0;
  for (double v : means) mb += v;
  mb /= double(means.size());
  double var = 0;
  for (double v : means) var += (v - mb) * (v - mb);
  var /= double(means.size() - 1);
  m.error = std::sqrt(var / double(means.size()));
  return m;
}

namespace {

// Mean and standard error of the first blocks·rows values of x in `blocks` blocks of `rows`.
MeanError blocks_of(std::span<const double> x, std::size_t rows, std::size_t blocks) {
  std::vector<double> means(blocks, 0.0);
  for (std::size_t b = 0; b < blocks; ++b) {
    for (std::size_t i = b * rows; i < (b + 1) * rows; ++i) means[b] += x[i];
    means[b] /= double(rows);
  }
  double m = 0;
  for (double v : means) m += v;
  m /= double(blocks);
  double var = 0;
  for (double v : means) var += (v - m) * (v - m);
  var /= double(blocks - 1);
  return {m, std::sqrt(var / double(blocks))};
}

}  // namespace

BlockAverage block_average(std::span<const double> x, int min_blocks) {
  BlockAverage a;
  const std::size_t n = x.size();
  const std::size_t want = std::size_t(std::max(min_blocks, 2));
  if (n == 0) return {std::nan(""), kNoError};
  double mean = 0;
  for (double v : x) mean += v;
  mean /= double(n);
  a.mean = mean;
  if (n < 2 * want) return a;
  double c0 = 0;
  for (double v : x) c0 += (v - mean) * (v - mean);
  c0 /= double(n);
  a.tau_int = 0.5;
  if (c0 > 0)
    for (std::size_t k = 1; k < n / 2; ++k) {
      double ck = 0;
      for (std::size_t i = 0; i + k < n; ++i) ck += (x[i] - mean) * (x[i + k] - mean);
      a.tau_int += ck / double(n) / c0;
      if (double(k) >= 5 * a.tau_int) break;  // Sokal's window: beyond it the sum is noise
    }
  a.tau_int = std::max(a.tau_int, 0.5);  // anticorrelated noise: blocks of single rows are honest enough
  std::size_t rows = std::size_t(std::ceil(20 * a.tau_int));
  a.long_enough = n / rows >= want;
  if (!a.long_enough) rows = n / want;
  a.block_rows = rows;
  a.blocks = n / rows;
  // The blocks' mean is the mean of the rows they cover (the last n mod L rows are left out).
  const MeanError m = blocks_of(x, rows, a.blocks);
  a.mean = m.mean;
  a.error = m.error;
  return a;
}

}  // namespace grainflow::scenes
