#pragma once
// A background thread running jobs in order, so the window stays responsive while the engine
// renders or segments. With `latest_only`, a new job replaces any that has not started yet
// (frames: only the newest view matters). Results come back through an Inbox the main thread
// drains once per frame.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pg::viewer {

class Inbox {
public:
    void post(std::function<void()> fn);
    void drain();  // runs everything posted so far, on the calling (main) thread
    std::function<void()> wake;  // called after each post (glfwPostEmptyEvent)

private:
    std::mutex mutex_;
    std::vector<std::function<void()>> items_;
};

class Worker {
public:
    explicit Worker(bool latest_only = false);
    ~Worker();  // finishes the running job, drops queued ones
    Worker(const Worker&) = delete;
    Worker& operator=(const Worker&) = delete;

    void post(std::function<void()> job);
    bool busy() const;  // a job queued or running

private:
    void loop();
    bool latest_only_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::function<void()>> jobs_;
    bool running_ = false, stop_ = false;
    std::thread thread_;
};

}  // namespace pg::viewer
