#include "scene/event_queue.h"

#include <algorithm>

namespace pbdsplat::scene {

EventQueue::EventQueue(const std::vector<Event>& scripted) {
    for (const Event& e : scripted) push(e, false);
}

void EventQueue::push(const Event& e, bool from_user) {
    const auto at = std::upper_bound(events_.begin(), events_.end(), e.time,
                                     [](float t, const QueuedEvent& q) { return t < q.event.time; });
    events_.insert(at, QueuedEvent{e, from_user});
}

std::vector<QueuedEvent> EventQueue::take_due(float end, const std::function<bool(const EventData&)>& wanted) {
    std::vector<QueuedEvent> due;
    auto keep = events_.begin();
    for (auto it = events_.begin(); it != events_.end(); ++it) {
        if (it->event.time < end && wanted(it->event.data)) {
            due.push_back(std::move(*it));
        } else {
            if (keep != it) *keep = std::move(*it);
            ++keep;
        }
    }
    events_.erase(keep, events_.end());
    return due;
}

bool EventQueue::any(const std::function<bool(const EventData&)>& wanted) const {
    return std::any_of(events_.begin(), events_.end(), [&](const QueuedEvent& q) { return wanted(q.event.data); });
}

bool is_topology_event(const EventData& d) { return std::holds_alternative<CutEvent>(d) || std::holds_alternative<TearEvent>(d); }

} // namespace pbdsplat::scene
