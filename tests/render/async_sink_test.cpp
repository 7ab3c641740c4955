#include "render/output/async_sink.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/core/error.hpp"
#include "render/output/fan_out_sink.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

using namespace std::chrono_literals;

// Records what reaches it and on which thread; can be held closed (gate) or made to fail.
struct Probe {
  std::mutex m;
  std::condition_variable cv;
  bool gate_open = true;
  std::vector<std::int64_t> indices;
  std::vector<int> first_bytes;
  std::vector<double> times;
  std::thread::id thread;
  int finished = 0;
  int destroyed = 0;
  std::int64_t fail_at = -1;
  std::vector<std::size_t> synced_after;  // frames consumed when each sync() ran
  bool fail_sync = false;
  std::chrono::milliseconds consume_delay{0};
};

class ProbeSink : public FrameSink {
public:
  explicit ProbeSink(Probe& p) : p_(p) {}
  ~ProbeSink() override {
    std::lock_guard l(p_.m);
    ++p_.destroyed;
  }
  void consume(const Image& frame, std::int64_t index, double time) override {
    std::unique_lock l(p_.m);
    p_.cv.wait(l, [&] { return p_.gate_open; });
    if (index == p_.fail_at) throw Error("disk full while writing frame " + std::to_string(index));
    if (p_.consume_delay.count() > 0) std::this_thread::sleep_for(p_.consume_delay);
    p_.indices.push_back(index);
    p_.first_bytes.push_back(frame.rgba.empty() ? -1 : frame.rgba[0]);
    p_.times.push_back(time);
    p_.thread = std::this_thread::get_id();
  }
  void finish() override {
    std::lock_guard l(p_.m);
    ++p_.finished;
  }
  void sync() override {
    std::lock_guard l(p_.m);
    if (p_.fail_sync) throw Error("cannot flush the encoder");
    p_.synced_after.push_back(p_.indices.size());
  }

private:
  Probe& p_;
};

Image tagged(int k) {
  Image im(4, 4);
  im.rgba[0] = static_cast<std::uint8_t>(k % 256);
  return im;
}

TEST(AsyncSink, DeliversEveryFrameInOrderToEverySinkOnAnotherThread) {
  Probe a, b;
  std::vector<std::unique_ptr<FrameSink>> sinks;
  sinks.push_back(std::make_unique<ProbeSink>(a));
  sinks.push_back(std::make_unique<ProbeSink>(b));
  AsyncSink async(std::move(sinks), 3);
  const int n = 200;
  for (int k = 0; k < n; ++k) {
    if (k % 2)
      async.consume(tagged(k), k, 0.25 * k);
    else
      async.consume(Image(tagged(k)), k, 0.25 * k);  // the moving overload
  }
  async.finish();
  for (Probe* p : {&a, &b}) {
    ASSERT_EQ(int(p->indices.size()), n);
    for (int k = 0; k < n; ++k) {
      ASSERT_EQ(p->indices[k], k);
      ASSERT_EQ(p->first_bytes[k], k % 256);
      ASSERT_EQ(p->times[k], 0.25 * k);
    }
    EXPECT_EQ(p->finished, 1);
    EXPECT_NE(p->thread, std::this_thread::get_id());
  }
  EXPECT_THROW(async.consume(tagged(0), n, 0.0), Error);
}

TEST(AsyncSink, ConsumeBlocksWhenQueueIsFull) {
  Probe p;
  p.gate_open = false;
  const std::size_t capacity = 2;
  AsyncSink async(std::make_unique<ProbeSink>(p), capacity);
  std::atomic<int> accepted{0};
  std::thread producer([&] {
    for (int k = 0; k < 10; ++k) {
      async.consume(tagged(k), k, 0.0);
      ++accepted;
    }
  });
  // One frame is held by the stalled sink, `capacity` wait in the queue; the next blocks.
  const int expected = int(capacity) + 1;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (accepted.load() < expected && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(1ms);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(accepted.load(), expected);
  {
    std::lock_guard l(p.m);
    p.gate_open = true;
  }
  p.cv.notify_all();
  producer.join();
  async.finish();
  EXPECT_EQ(p.indices.size(), 10u);
  EXPECT_GT(async.blocked_seconds(), 0.05);
}

TEST(AsyncSink, WorkerExceptionReachesTheProducer) {
  Probe p;
  p.fail_at = 3;
  AsyncSink async(std::make_unique<ProbeSink>(p), 4);
  std::string message;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  for (int k = 0; std::chrono::steady_clock::now() < deadline; ++k) {
    try {
      async.consume(tagged(k), k, 0.0);
    } catch (const Error& e) {
      message = e.what();
      break;
    }
    if (k > 10) std::this_thread::sleep_for(1ms);
  }
  EXPECT_EQ(message, "disk full while writing frame 3");
  EXPECT_THROW(async.finish(), Error);
  EXPECT_EQ(p.indices, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(p.finished, 0) << "a failed run must not finalise its outputs";
}

TEST(AsyncSink, FinishRethrowsAFailureNoConsumeSaw) {
  Probe p;
  p.fail_at = 0;
  AsyncSink async(std::make_unique<ProbeSink>(p), 4);
  async.consume(tagged(0), 0, 0.0);
  EXPECT_THROW(async.finish(), Error);
  EXPECT_EQ(p.finished, 0);
}

TEST(AsyncSink, DestroyedUnfinishedDoesNotFinishInnerSinks) {
  Probe p;
  {
    AsyncSink async(std::make_unique<ProbeSink>(p), 4);
    for (int k = 0; k < 5; ++k) async.consume(tagged(k), k, 0.0);
  }
  EXPECT_EQ(p.finished, 0);
  EXPECT_EQ(p.destroyed, 1);
  EXPECT_LE(p.indices.size(), 5u);
}

// sync() returns once the worker has written every frame queued before it and synced the
// inner sinks; the producer may go on queueing frames right after.
TEST(AsyncSink, SyncWaitsForTheQueueAndSyncsTheInnerSinks) {
  Probe a, b;
  a.consume_delay = 5ms;  // a slow encoder: frames are still queued when sync() is called
  std::vector<std::unique_ptr<FrameSink>> sinks;
  sinks.push_back(std::make_unique<ProbeSink>(a));
  sinks.push_back(std::make_unique<ProbeSink>(b));
  AsyncSink async(std::move(sinks), 3);
  async.sync();  // nothing queued
  for (int k = 0; k < 12; ++k) async.consume(tagged(k), k, 0.0);
  async.sync();
  for (Probe* p : {&a, &b}) {
    std::lock_guard l(p->m);
    EXPECT_EQ(p->indices.size(), 12u);
    EXPECT_EQ(p->synced_after, (std::vector<std::size_t>{0, 12}));
  }
  async.sync();  // twice in a row
  for (int k = 12; k < 20; ++k) async.consume(tagged(k), k, 0.0);
  async.finish();
  EXPECT_EQ(a.synced_after, (std::vector<std::size_t>{0, 12, 12}));
  EXPECT_EQ(a.indices.size(), 20u);
  EXPECT_EQ(a.finished, 1);
  EXPECT_THROW(async.sync(), Error) << "sync() after finish()";
}

TEST(AsyncSink, SyncRethrowsAWorkerFailure) {
  {
    Probe p;
    p.fail_at = 2;
    AsyncSink async(std::make_unique<ProbeSink>(p), 8);
    for (int k = 0; k < 5; ++k) async.consume(tagged(k), k, 0.0);
    try {
      async.sync();
      ADD_FAILURE() << "sync() hid the failure of frame 2";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), "disk full while writing frame 2");
    }
    EXPECT_TRUE(p.synced_after.empty());
    EXPECT_THROW(async.consume(tagged(5), 5, 0.0), Error);
  }
  {
    Probe p;
    p.fail_sync = true;
    AsyncSink async(std::make_unique<ProbeSink>(p), 8);
    async.consume(tagged(0), 0, 0.0);
    EXPECT_THROW(async.sync(), Error);
    EXPECT_THROW(async.finish(), Error);
    EXPECT_EQ(p.finished, 0);
  }
}

// FanOutSink asks every asynchronous worker to sync before waiting for any of them.
TEST(AsyncSink, FanOutSyncsEveryWorker) {
  Probe a, b;
  a.consume_delay = 3ms;
  std::vector<std::unique_ptr<FrameSink>> sinks;
  sinks.push_back(std::make_unique<ProbeSink>(a));
  sinks.push_back(std::make_unique<ProbeSink>(b));
  auto out = parallel_sinks(std::move(sinks), 2);
  for (int k = 0; k < 9; ++k) out->consume(tagged(k), k, 0.0);
  out->sync();
  for (Probe* p : {&a, &b}) {
    std::lock_guard l(p->m);
    EXPECT_EQ(p->synced_after, (std::vector<std::size_t>{9}));
  }
  out->finish();
}

TEST(AsyncSink, ZeroCapacityIsAnError) {
  Probe p;
  EXPECT_THROW(AsyncSink(std::make_unique<ProbeSink>(p), 0), Error);
}

TEST(AsyncSink, WrapsARealPngSequence) {
  const auto dir = test::fresh_dir();
  AsyncSink async(std::make_unique<PngSequenceSink>(dir / "frames"), 2);
  for (int k = 0; k < 6; ++k) async.consume(test::random_image(31, 17, k), k, 0.0);
  async.finish();
  for (int k = 0; k < 6; ++k)
    EXPECT_EQ(read_png(dir / "frames" / ("frame_00000" + std::to_string(k) + ".png")).rgba,
              test::random_image(31, 17, k).rgba);
}

}  // namespace
}  // namespace grainflow::render

// parallel_sinks(): every sink gets every frame, in order, and is finished.
TEST(ParallelSinks, EverySinkGetsEveryFrameInOrder) {
  struct Recorder : grainflow::render::FrameSink {
    std::vector<std::int64_t>* seen;
    bool* finished;
    Recorder(std::vector<std::int64_t>* s, bool* f) : seen(s), finished(f) {}
    void consume(const grainflow::render::Image&, std::int64_t index, double) override { seen->push_back(index); }
    void finish() override { *finished = true; }
  };
  std::vector<std::int64_t> a, b;
  bool fa = false, fb = false;
  std::vector<std::unique_ptr<grainflow::render::FrameSink>> sinks;
  sinks.push_back(std::make_unique<Recorder>(&a, &fa));
  sinks.push_back(std::make_unique<Recorder>(&b, &fb));
  auto out = grainflow::render::parallel_sinks(std::move(sinks), 2);
  const grainflow::render::Image img(8, 4);
  for (int i = 0; i < 50; ++i) out->consume(img, i, 0.1 * i);
  out->finish();
  ASSERT_EQ(a.size(), 50u);
  ASSERT_EQ(b.size(), 50u);
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(a[i], i);
    EXPECT_EQ(b[i], i);
  }
  EXPECT_TRUE(fa && fb);
}
