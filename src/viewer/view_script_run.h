// A view script (view_script.h) run in the viewer's loop: one action per displayed frame. Before
// each frame the runner waits while the session refines a frame or the timeline's frame is
// still loading, counts a {"frames": N} action down, or applies the next action to the
// session, the debug view, the timeline or the panel's open sections; after the frame is
// drawn it writes what an output action asks for (screenshots, the render command, the
// status), so an output sees the frame its action came with.
#pragma once

#include "viewer/debug_view.h"
#include "viewer/session/timeline_player.h"
#include "viewer/session/view_session.h"
#include "viewer/view_script.h"

#include <cstddef>
#include <set>
#include <string>
#include <vector>

namespace veil::viewer {

// What a script acts on.
struct ScriptTarget {
    session::ViewSession& session;
    DebugView& view;
    session::TimelinePlayer& timeline;
    std::set<std::string>& expand; // {"expand": [...]}: the panel sections to open
};

class ScriptRunner {
public:
    // `path`: the script's file (messages, and outputs must not overwrite it); "" with no
    // actions: no script (the runner does nothing).
    ScriptRunner(std::vector<ScriptAction> actions, std::string path);

    // Before a frame. Returns true when the frame must render even if nothing changed (a
    // frame counted by a "frames" action).
    bool beforeFrame(const ScriptTarget& target);
    // After the frame is drawn into the window (`width` x `height`, the back buffer not yet
    // shown): the output of this frame's action, if it has one.
    void afterFrame(const session::ViewSession& session, const DebugView& view, int width,
                    int height);
    // A script was given and is done: every action applied, no frames left to wait and no
    // refinement in progress.
    bool finished(const session::ViewSession& session) const;

private:
    std::vector<ScriptAction> actions_;
    std::string path_;
    std::size_t next_ = 0;               // the next action
    int wait_ = 0;                       // frames left of a "frames" action
    const ScriptAction* this_ = nullptr; // the action applied before this frame
};

} // namespace veil::viewer
