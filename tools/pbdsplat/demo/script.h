#pragma once
// Scripted input: the actions a person would perform (drags, cut strokes, key presses) at
// given frames, in window pixels, turned into the same input events the window delivers.
//
//   # comment
//   10 drag 640 360 700 300 20    frame, from x y, to x y, over frames (default 10)
//   40 cut 560 160 760 600        a right-button stroke, drawn over 4 frames
//   50 key P                      a letter or digit, or space, escape, f1, up, down, tab, plus, minus
//   60 orbit 120 0 10             a left-button drag on empty space: turns the camera
//   70 scroll 2                   zoom in two steps
#include <map>
#include <string>
#include <vector>

#include "demo/window.h"

namespace pbdsplat::demo {

class InputScript {
public:
    // Errors name the file, the line and what is wrong.
    static core::Result<InputScript> load(const std::string& path);
    static core::Result<InputScript> parse(const std::string& text, const std::string& name);

    // The events of frame `frame` (0 = the first frame).
    std::vector<InputEvent> events_at(uint64_t frame) const;
    uint64_t last_frame() const { return events_.empty() ? 0 : events_.rbegin()->first; }

private:
    std::map<uint64_t, std::vector<InputEvent>> events_;
    void add_stroke(uint64_t frame, int button, Vec2f from, Vec2f to, uint32_t frames);
};

} // namespace pbdsplat::demo
