// Runs frame sinks on their own thread behind a bounded queue, so PNG compression and
// H.264 encoding overlap with the simulation and rendering (ARCHITECTURE.md, "Data flow").
#pragma once
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "render/output/frame_sink.hpp"

namespace grainflow::render {

class AsyncSink : public FrameSink {
public:
  // `capacity` frames may wait in the queue (one more is being written by the worker);
  // consume() blocks while the queue is full, so memory stays bounded (a 1080p frame is
  // 8 MB) and a slow disk or encoder slows the producer instead of growing the queue.
  explicit AsyncSink(std::vector<std::unique_ptr<FrameSink>> sinks, std::size_t capacity = 4);
  explicit AsyncSink(std::unique_ptr<FrameSink> sink, std::size_t capacity = 4);
  // Without finish(): stops the worker, drops queued frames and destroys the inner sinks
  // unfinished, so they leave no finished-looking file.
  ~AsyncSink() override;
  AsyncSink(const AsyncSink&) = delete;
  AsyncSink& operator=(const AsyncSink&) = delete;

  // Copies the frame into the queue. If a sink failed on the worker, its exception is
  // re-thrown here (and at every later call).
  void consume(const Image& frame, std::int64_t index, double time) override;
  // Moves the frame into the queue: no copy.
  void consume(Image&& frame, std::int64_t index, double time);
  // Writes everything queued, joins the worker, then finishes each inner sink in order.
  // Re-throws a worker failure.
  void finish() override;
  // Returns once the worker has consumed every frame queued before the call and then run
  // sync() on each inner sink in order. Re-throws a worker failure met before that point
  // (a failure in a later frame is reported by the next call instead). Equivalent to
  // wait_synced(request_sync()).
  void sync() override;
  // The two halves of sync(), so that FanOutSink syncs its workers in parallel: queue a
  // sync marker (behind the queued frames; queued even when the queue is full) and get
  // its ticket; then wait until the worker has passed that marker.
  std::uint64_t request_sync();
  void wait_synced(std::uint64_t ticket);

  std::size_t capacity() const { return capacity_; }
  // Total time consume() waited for room in the queue (seconds): how much the sinks held
  // the producer back.
  double blocked_seconds() const;

private:
  struct Item {
    Image frame;
    std::int64_t index = 0;
    double time = 0.0;
    bool sync = false;  // not a frame: run sync() on the inner sinks
  };
  void push(Item item);
  void run();
  void stop_worker();
  void rethrow_if_failed();  // call with mutex_ held

  std::vector<std::unique_ptr<FrameSink>> sinks_;
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_;
  std::condition_variable not_empty_;
  std::condition_variable synced_;
  std::uint64_t syncs_requested_ = 0;
  std::uint64_t syncs_done_ = 0;
  std::deque<Item> queue_;
  bool closing_ = false;   // no more frames will come: drain and exit
  bool aborting_ = false;  // exit now, drop the queue
  bool finished_ = false;
  std::exception_ptr error_;
  double blocked_seconds_ = 0.0;
  std::thread worker_;
};

}  // namespace grainflow::render
