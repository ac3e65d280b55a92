// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/compute_worker.h"

namespace hf::compute {

ComputeWorker::ComputeWorker(std::function<std::unique_ptr<Device>()> make_device) {
  std::promise<void> ready;
  std::future<void> started = ready.get_future();
  thread_ = std::thread([this, make_device, &ready] { loop(make_device, ready); });
  try {
    started.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

ComputeWorker::~ComputeWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void ComputeWorker::post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void ComputeWorker::loop(const std::function<std::unique_ptr<Device>()>& make_device, std::promise<void>& ready) {
  std::unique_ptr<Device> device;
  try {
    device = make_device();
    info_ = device->info();
  } catch (...) {
    ready.set_exception(std::current_exception());
    return;
  }
  DeviceScope scope(*device);
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

}  // namespace hf::compute
