#include "scenes/src/outputs/run_record.hpp"

#include <ctime>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"
#include "scenes/src/outputs/json_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

#ifndef GRAINFLOW_VERSION
#define GRAINFLOW_VERSION "unknown"
#endif

namespace grainflow::scenes {

std::string_view run_status_name(RunStatus s) {
  switch (s) {
    case RunStatus::Running: return "running";
    case RunStatus::Complete: return "complete";
    case RunStatus::Interrupted: return "interrupted";
    case RunStatus::Failed: return "failed";
  }
  return "?";
}

std::string utc_now_iso8601() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

RunRecord make_run_record(const Scene& scene) {
  RunRecord r;
  r.version = GRAINFLOW_VERSION;
  r.engine = scene.engine();
  r.seed = scene.get(run_keys::seed);
  r.title = scene.get(run_keys::title);
  r.scene = scene.source().string();
  r.overrides = scene.overrides();
  r.started_utc = utc_now_iso8601();
  if (auto until = scene.find(run_keys::until)) {
    r.target = *until;
    r.target_kind = "until";
  } else {
    r.target = double(scene.get(run_keys::steps));
    r.target_kind = "steps";
  }
  return r;
}

std::string run_record_json(const RunRecord& r) {
  JsonWriter w;
  w.begin_object();
  w.key("grainflow_version").value(r.version);
  w.key("status").value(run_status_name(r.status));
  if (!r.error.empty()) w.key("error").value(r.error);
  w.key("engine").value(r.engine);
  w.key("seed").value(r.seed);
  w.key("title").value(r.title);
  w.key("scene").value(r.scene);
  w.key("overrides").begin_array();
  for (const auto& o : r.overrides) w.value(o);
  w.end_array();
  w.key("backend").value(r.backend);
  w.key("started_utc").value(r.started_utc);
  w.key("resumes").value(r.resumes);
  w.key("checkpoints").value(r.checkpoints);
  w.key("checkpoint_seconds").value(r.checkpoint_seconds);
  w.key("wall_time_s").value(r.wall_time_s);
  w.key("sim_time").value(r.sim_time);
  w.key(r.target_kind.empty() ? "target" : r.target_kind).value(r.target);
  w.key("frames").value(r.frames);
  w.key("throughput").begin_object();
  for (const auto& t : r.throughput) {
    w.key(t.name).begin_object();
    w.key("per_second").value(t.per_second);
    w.key("unit").value(t.unit);
    w.end_object();
  }
  w.end_object();
  w.key("figures").begin_object();
  for (const auto& [k, v] : r.figures) w.key(k).value(v);
  w.end_object();
  if (!r.state_digest.empty()) w.key("state_digest").value(r.state_digest);
  w.end_object();
  return w.str() + "\n";
}

void write_run_record(const RunRecord& r, const std::filesystem::path& path) {
  io::write_text_atomically(path, run_record_json(r));
}

namespace {

// run.json: written when the run starts ("running"), at its end and when it fails.
class RunJsonOutput final : public RunOutput {
public:
  explicit RunJsonOutput(std::filesystem::path file) : file_(std::move(file)) {}
  void start(const RunRecord& r) override { write_run_record(r, file_); }
  // The record is rewritten whole from the run's figures: nothing to carry over.
  void checkpoint(io::ArchiveWriter&) override {}
  void resume(io::ArchiveReader&, const RunRecord& r) override { write_run_record(r, file_); }
  void progress(const RunRecord& r) override { write_run_record(r, file_); }
  void finish(const RunRecord& r) override { write_run_record(r, file_); }
  void fail(const RunRecord& r) override { write_run_record(r, file_); }

private:
  std::filesystem::path file_;
};

void declare_nothing(Schema&) {}

std::unique_ptr<RunOutput> open_run_json(const OutputContext& c) {
  c.claim("run.json");
  return std::make_unique<RunJsonOutput>(c.dir / "run.json");
}

}  // namespace

OutputEntry run_json_output() {
  return {"run.json", "run.json: how the run was made and how it went", &declare_nothing, nullptr, &open_run_json};
}

}  // namespace grainflow::scenes
