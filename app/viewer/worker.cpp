#include "app/viewer/worker.h"

namespace pg::viewer {

void Inbox::post(std::function<void()> fn) {
    {
        std::lock_guard lock(mutex_);
        items_.push_back(std::move(fn));
    }
    if (wake) wake();
}

void Inbox::drain() {
    std::vector<std::function<void()>> items;
    {
        std::lock_guard lock(mutex_);
        items.swap(items_);
    }
    for (auto& fn : items) fn();
}

Worker::Worker(bool latest_only) : latest_only_(latest_only), thread_([this] { loop(); }) {}

Worker::~Worker() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        jobs_.clear();
    }
    cv_.notify_all();
    thread_.join();
}

void Worker::post(std::function<void()> job) {
    {
        std::lock_guard lock(mutex_);
        if (latest_only_) jobs_.clear();
        jobs_.push_back(std::move(job));
    }
    cv_.notify_all();
}

bool Worker::busy() const {
    std::lock_guard lock(mutex_);
    return running_ || !jobs_.empty();
}

void Worker::loop() {
    for (;;) {
        std::function<void()> job;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
            if (stop_) return;
            job = std::move(jobs_.front());
            jobs_.pop_front();
            running_ = true;
        }
        job();  // jobs catch their own errors and report them through the inbox
        std::lock_guard lock(mutex_);
        running_ = false;
    }
}

}  // namespace pg::viewer
