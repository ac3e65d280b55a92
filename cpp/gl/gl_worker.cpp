// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_worker.h"

namespace hf::gl {

GlWorker::GlWorker(const std::string& device_request) {
  std::promise<void> ready;
  std::future<void> started = ready.get_future();
  thread_ = std::thread([this, device_request, &ready] { loop(device_request, ready); });
  try {
    started.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

GlWorker::~GlWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void GlWorker::post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void GlWorker::loop(const std::string& device_request, std::promise<void>& ready) {
  std::unique_ptr<EglContext> context;
  try {
    context = std::make_unique<EglContext>(device_request);
    info_ = context->info();
  } catch (...) {
    ready.set_exception(std::current_exception());
    return;
  }
  ready.set_value();
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) break;  // stopping, and nothing left to run
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // packaged_task stores any exception for the caller
  }
}

}  // namespace hf::gl
