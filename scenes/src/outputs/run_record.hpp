// run.json (SPEC.md §3b): how a run was made and how it went — version, engine, seed,
// backend, wall time, throughput, status. Written when the run starts, refreshed
// periodically and at the end, always atomically, so it never reads half-written.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace grainflow::scenes {

class Scene;

enum class RunStatus { Running, Complete, Interrupted, Failed };
std::string_view run_status_name(RunStatus s);  // "running", "complete", "interrupted", "failed"

struct Throughput {
  std::string name;  // "collisions", "steps", "frames"
  double per_second = 0;
  std::string unit;  // "collisions/s"
};

struct RunRecord {
  std::string version;  // grainflow version
  std::string engine;
  std::int64_t seed = 0;
  std::string title;
  std::string scene;  // scene file path as given
  std::vector<std::string> overrides;
  std::string backend;      // GL backend actually used ("egl (llvmpipe)"), or the requested one
  std::string started_utc;  // ISO 8601
  std::int64_t resumes = 0;  // times the run was continued from a checkpoint (--resume)
  std::int64_t checkpoints = 0;   // written by this session
  double checkpoint_seconds = 0;  // wall time they took
  RunStatus status = RunStatus::Running;
  std::string error;  // set when status is Failed
  double wall_time_s = 0;
  double sim_time = 0;      // simulated time reached
  double target = 0;        // run.until or run.steps
  std::string target_kind;  // "until" | "steps"
  std::int64_t frames = 0;
  std::vector<Throughput> throughput;
  std::vector<std::pair<std::string, double>> figures;  // other totals (events, collisions, …)
  std::string state_digest;  // EngineRunner::state_digest() at the end of the run
};

// Fills version, engine, seed, title, scene, overrides, target and the start time from a
// validated scene (the run loop adds the GL backend it got).
RunRecord make_run_record(const Scene& scene);

std::string run_record_json(const RunRecord& r);
// Writes run_record_json(r) to `path` via a temporary name and rename.
void write_run_record(const RunRecord& r, const std::filesystem::path& path);

// Now as "2024-05-01T12:34:56Z".
std::string utc_now_iso8601();

}  // namespace grainflow::scenes
