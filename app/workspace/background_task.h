// Long work off the UI thread (bind, automatic cage, ...): the UI polls progress every frame,
// may cancel, and takes the result once done. The work receives a progress callback (share in
// [0, 1] and a stage name) and the cancel flag, and returns a Result (kCancelled when it stopped).
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/base/result.h"

namespace cagewrap::app {

template <class T>
class BackgroundTask {
 public:
  using Progress = std::function<void(const char* stage, double share)>;
  using Work = std::function<Result<T>(const Progress& progress, const std::atomic<bool>& cancel)>;

  BackgroundTask(std::string label, Work work) : label_(std::move(label)) {
    thread_ = std::thread([this, work = std::move(work)] {
      Progress progress = [this](const char* stage, double share) {
        progress_ = share;
        std::lock_guard lock(mutex_);
        stage_ = stage ? stage : "";
      };
      result_.emplace(work(progress, cancel_));
      done_ = true;
    });
  }
  ~BackgroundTask() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
  }
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;

  const std::string& label() const { return label_; }
  double progress() const { return progress_.load(); }
  std::string stage() const {
    std::lock_guard lock(mutex_);
    return stage_;
  }
  bool done() const { return done_.load(); }
  void cancel() { cancel_ = true; }
  bool cancelling() const { return cancel_.load(); }
  // Valid once done().
  Result<T>& result() {
    if (thread_.joinable()) thread_.join();
    return *result_;
  }

 private:
  std::string label_;
  std::atomic<double> progress_{0.0};
  std::atomic<bool> cancel_{false}, done_{false};
  mutable std::mutex mutex_;
  std::string stage_;
  std::optional<Result<T>> result_;
  std::thread thread_;
};

}  // namespace cagewrap::app
