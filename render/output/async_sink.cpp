#include "render/output/async_sink.hpp"

#include <chrono>
#include <utility>

#include "engine/core/error.hpp"

namespace grainflow::render {

AsyncSink::AsyncSink(std::vector<std::unique_ptr<FrameSink>> sinks, std::size_t capacity)
    : sinks_(std::move(sinks)), capacity_(capacity) {
  if (capacity_ == 0) throw Error("asynchronous output: queue capacity 0 is not allowed (at least 1 frame)");
  for (const auto& s : sinks_)
    if (!s) throw Error("asynchronous output: a null sink was given");
  worker_ = std::thread([this] { run(); });
}

namespace {
std::vector<std::unique_ptr<FrameSink>> one(std::unique_ptr<FrameSink> sink) {
  std::vector<std::unique_ptr<FrameSink>> v;
  v.push_back(std::move(sink));
  return v;
}
}  // namespace

AsyncSink::AsyncSink(std::unique_ptr<FrameSink> sink, std::size_t capacity) : AsyncSink(one(std::move(sink)), capacity) {}

AsyncSink::~AsyncSink() {
  {
    std::lock_guard lock(mutex_);
    aborting_ = true;
    queue_.clear();
  }
  stop_worker();
}

void AsyncSink::stop_worker() {
  not_empty_.notify_all();
  not_full_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void AsyncSink::rethrow_if_failed() {
  if (error_) std::rethrow_exception(error_);
}

void AsyncSink::consume(const Image& frame, std::int64_t index, double time) { push(Item{frame, index, time}); }

void AsyncSink::consume(Image&& frame, std::int64_t index, double time) {
  push(Item{std::move(frame), index, time});
}

void AsyncSink::push(Item item) {
  std::unique_lock lock(mutex_);
  if (finished_ || closing_) throw Error("asynchronous output: consume() after finish()");
  rethrow_if_failed();
  if (queue_.size() >= capacity_) {
    const auto t0 = std::chrono::steady_clock::now();
    not_full_.wait(lock, [this] { return queue_.size() < capacity_ || error_; });
    blocked_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rethrow_if_failed();
  }
  queue_.push_back(std::move(item));
  lock.unlock();
  not_empty_.notify_one();
}

void AsyncSink::run() {
  for (;;) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      not_empty_.wait(lock, [this] { return !queue_.empty() || closing_ || aborting_; });
      if (aborting_ || queue_.empty()) return;  // queue empty here means closing_
      item = std::move(queue_.front());
      queue_.pop_front();
    }
    if (!item.sync) not_full_.notify_one();
    try {
      if (item.sync) {
        for (auto& sink : sinks_) sink->sync();
        {
          std::lock_guard lock(mutex_);
          ++syncs_done_;
        }
        synced_.notify_all();
      } else {
        for (auto& sink : sinks_) sink->consume(item.frame, item.index, item.time);
      }
    } catch (...) {
      std::lock_guard lock(mutex_);
      error_ = std::current_exception();
      queue_.clear();
      not_full_.notify_all();
      synced_.notify_all();
      return;
    }
  }
}

std::uint64_t AsyncSink::request_sync() {
  std::unique_lock lock(mutex_);
  if (finished_ || closing_) throw Error("asynchronous output: sync() after finish()");
  rethrow_if_failed();
  Item marker;
  marker.sync = true;
  queue_.push_back(std::move(marker));
  const std::uint64_t ticket = ++syncs_requested_;
  lock.unlock();
  not_empty_.notify_one();
  return ticket;
}

void AsyncSink::wait_synced(std::uint64_t ticket) {
  std::unique_lock lock(mutex_);
  synced_.wait(lock, [&] { return syncs_done_ >= ticket || error_; });
  if (syncs_done_ >= ticket) return;
  rethrow_if_failed();
}

void AsyncSink::sync() { wait_synced(request_sync()); }

void AsyncSink::finish() {
  {
    std::lock_guard lock(mutex_);
    if (finished_) throw Error("asynchronous output: finish() called twice");
    finished_ = true;
    closing_ = true;
  }
  stop_worker();
  {
    std::lock_guard lock(mutex_);
    rethrow_if_failed();
  }
  for (auto& sink : sinks_) sink->finish();
}

double AsyncSink::blocked_seconds() const {
  std::lock_guard lock(mutex_);
  return blocked_seconds_;
}

}  // namespace grainflow::render
