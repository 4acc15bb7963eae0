#include "demo/script.h"

#include <cctype>
#include <cmath>
#include <optional>
#include <fstream>
#include <sstream>

namespace pbdsplat::demo {

namespace {
std::optional<int> key_code(const std::string& name) {
    if (name.size() == 1 && std::isalnum(static_cast<unsigned char>(name[0])))
        return std::toupper(static_cast<unsigned char>(name[0]));
    static const std::pair<const char*, int> names[] = {{"space", key_space}, {"escape", key_escape}, {"f1", key_f1},
                                                        {"up", key_up},       {"down", key_down},     {"tab", key_tab},
                                                        {"plus", key_plus},   {"minus", key_minus}};
    for (const auto& [n, k] : names)
        if (name == n) return k;
    return std::nullopt;
}
} // namespace

core::Result<InputScript> InputScript::load(const std::string& path) {
    std::ifstream in(path);
    if (!in) return core::make_error(path + ": cannot open the input script");
    std::stringstream text;
    text << in.rdbuf();
    return parse(text.str(), path);
}

void InputScript::add_stroke(uint64_t frame, int button, Vec2f from, Vec2f to, uint32_t frames) {
    InputEvent down;
    down.kind = InputEvent::Kind::press;
    down.button = button;
    down.position = from;
    events_[frame].push_back(down);
    for (uint32_t k = 1; k <= frames; ++k) {
        InputEvent move;
        move.kind = InputEvent::Kind::move;
        move.position = from + (to - from) * (float(k) / float(frames));
        events_[frame + k].push_back(move);
    }
    InputEvent up = down;
    up.kind = InputEvent::Kind::release;
    up.position = to;
    events_[frame + frames + 1].push_back(up);
}

core::Result<InputScript> InputScript::parse(const std::string& text, const std::string& name) {
    InputScript s;
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream in(line);
        std::string first;
        if (!(in >> first)) continue;
        auto fail = [&](const std::string& what) { return core::make_error(name + ":" + std::to_string(number) + ": " + what); };
        uint64_t frame = 0;
        try {
            size_t used = 0;
            const long long f = std::stoll(first, &used);
            if (used != first.size() || f < 0) throw std::invalid_argument("frame");
            frame = uint64_t(f);
        } catch (const std::exception&) {
            return fail("a line starts with its frame number (0 or more), not '" + first + "'");
        }
        std::string action;
        if (!(in >> action)) return fail("frame " + first + " names no action (drag, cut, key, orbit or scroll)");
        auto numbers = [&](size_t need, size_t allow, std::vector<float>& out) -> bool {
            float v = 0.0f;
            while (in >> v) {
                if (!std::isfinite(v)) return false;
                out.push_back(v);
            }
            in.clear();
            std::string rest;
            return !(in >> rest) && out.size() >= need && out.size() <= allow;
        };
        std::vector<float> v;
        if (action == "drag" || action == "orbit" || action == "cut") {
            if (!numbers(4, 5, v)) return fail(action + " takes: from-x from-y to-x to-y [frames]");
            const float frames = v.size() == 5 ? v[4] : (action == "cut" ? 4.0f : 10.0f);
            if (frames < 1.0f || frames > 100000.0f) return fail(action + ": frames must be 1 to 100000");
            // An orbit is a drag that starts on empty space; the app tells them apart by what
            // lies under the cursor, so both are left-button strokes.
            s.add_stroke(frame, action == "cut" ? 1 : 0, {v[0], v[1]}, {v[2], v[3]}, uint32_t(frames));
        } else if (action == "key") {
            std::string k, rest;
            if (!(in >> k) || (in >> rest)) return fail("key takes one key name");
            const auto code = key_code(k);
            if (!code) return fail("unknown key '" + k + "' (a letter or digit, space, escape, f1, up, down, tab, plus, minus)");
            InputEvent e;
            e.kind = InputEvent::Kind::key;
            e.key = *code;
            s.events_[frame].push_back(e);
        } else if (action == "scroll") {
            if (!numbers(1, 1, v)) return fail("scroll takes one number of steps (up positive)");
            InputEvent e;
            e.kind = InputEvent::Kind::scroll;
            e.scroll = v[0];
            s.events_[frame].push_back(e);
        } else {
            return fail("unknown action '" + action + "' (drag, cut, key, orbit or scroll)");
        }
    }
    return s;
}

std::vector<InputEvent> InputScript::events_at(uint64_t frame) const {
    const auto it = events_.find(frame);
    return it == events_.end() ? std::vector<InputEvent>{} : it->second;
}

} // namespace pbdsplat::demo
