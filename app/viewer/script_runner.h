#pragma once
// Replays a script through the viewer's public actions, one action once everything the
// previous one started has finished and shown; then saves the final screenshot and quits.
#include <fstream>
#include <string>
#include <vector>

#include "app/viewer/script.h"

namespace pg::viewer {

class Viewer;

class ScriptRunner {
public:
    // `log`: if not empty, a JSON line per settled action (action index and kind, host RSS and
    // live device memory in bytes), for soak runs.
    ScriptRunner(std::vector<Action> actions, std::string final_screenshot, const std::string& log = {});

    // Once per window frame, before it is drawn; `idle`: the viewer's state at this frame.
    void step(Viewer& viewer, bool idle);
    bool settled() const { return idle_frames_ >= 1; }  // a screenshot taken now shows the last action
    bool finished() const { return finished_; }

private:
    void run(Viewer& viewer, const Action& action);
    void log_settled();

    std::vector<Action> actions_;
    std::string final_screenshot_;
    size_t next_ = 0;
    int idle_frames_ = 0;
    bool finished_ = false;
    std::ofstream log_;
};

}  // namespace pg::viewer
