#pragma once
// Every event of a run in one queue, in time order: the scene's timed events and the user's cut
// strokes (due at the next frame). The events pass takes the timeline's kinds (pressure, drags,
// spins, opacity) as they fall due, the topology pass the cuts and tears; neither keeps a list of
// its own, and a stroke and a scripted cut meet in one order.
#include <functional>
#include <vector>

#include "scene/scene.h"

namespace pbdsplat::scene {

struct QueuedEvent {
    Event event;
    // A stroke from the window: its outcome is noted for the user, and a stroke that fails does
    // not stop the run (a scripted event that fails does).
    bool from_user = false;
};

class EventQueue {
public:
    explicit EventQueue(const std::vector<Event>& scripted);

    // Queued after every event of the same time or earlier.
    void push(const Event& e, bool from_user);
    // Removes and returns, in time order, the events before `end` that `wanted` accepts.
    std::vector<QueuedEvent> take_due(float end, const std::function<bool(const EventData&)>& wanted);
    bool any(const std::function<bool(const EventData&)>& wanted) const;

private:
    std::vector<QueuedEvent> events_;  // time order, stable for equal times
};

// The kinds the topology stage takes: cuts and tears.
bool is_topology_event(const EventData& d);

} // namespace pbdsplat::scene
