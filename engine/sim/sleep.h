#pragma once
// Pieces that have come to rest sleep: their particles are held (inverse mass 0, no velocity)
// until something acts on them. A stack of PBD contacts never rests by itself: its pieces jitter
// at a few centimetres a second and creep long after they land, and each creeping particle sets
// the contact search off again (docs/BENCHMARKS.md, "Contact"). Asleep, a piece is what a static
// body is to every stage (pushed against, never moved), so nothing else changes.
//
// A piece is still while none of its particles leaves a ball of `radius` mean rest edges about
// where it was when the still spell began and they move slowly; still for `time`, it sleeps,
// unless a piece touching it moved fast within that time. A sleeping piece wakes when a piece touching it moves (one
// dropped onto it, or what it rests on sliding away), at the frame's end, or at once when a contact presses it deeper than the thickness (wake_pieces); a
// static body never sleeps, being held already. Whatever acts on the body from outside (a cut, a
// tear, a drag, a spin, a pressure ramp) wakes every piece first: sim::wake_all, called where it
// acts. Pieces sleep one by one, not as islands: a piece that keeps creeping beside a resting
// one would keep the island awake, and in the pile that was every island. Pieces joined by welds
// (a model's parts held together: sim/weld.h) are the exception: they sleep and wake as one, since
// a held piece would hold its end of the welds while the rest pulls on it.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/math.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

template <class Real>
struct SoftBodyT;
template <class Real>
struct BodyStateT;

struct SleepSettings {
    bool enabled = true;  // a user expects a pile that landed to lie still
    // Seconds still before a piece sleeps: long enough that a piece rocking to rest (a half
    // ball in its ring swings with a period of about 0.2 s) is seen to stop.
    float time = 0.5f;
    // Mean rest edges a particle may wander from where its piece's still spell began. Resting
    // pieces jitter and creep: in the pile a block on the ground moved 0.1-0.2 edges in half a
    // second and pieces stacked on it up to 0.4 (at 0.15 and 0.3 edges most never slept); a
    // piece that slides, rolls or tips leaves half an edge within a few frames.
    float radius = 0.5f;
    // Mean rest edges the piece as a whole (its particles' mean) may drift in the still spell:
    // a box on a slope just past its friction angle starts slowly (0.66 m/s^2 at 30 degrees and
    // mu 0.5: 8 cm in half a second, a third of its 25 cm edges) and must not be held; at 0.1
    // edges resting stacks creeping a centimetre a second seldom slept.
    float drift = 0.25f;
    // Mean rest edges a second the piece's particles may move at (their rms speed) and count as
    // still: a piece swinging within the radius is not at rest. A 0.2 kg ball bouncing on a soft
    // box (0.45 m/s, 7 edges a second) kept it awake by the radius alone; the box fell asleep
    // under it, deformed, and flung it 1.5 m/s up, again and again. Resting pieces in the shipped
    // stacks fall asleep at up to 2 edges a second.
    float speed = 3.0f;
};

// The sleep of a body's pieces: part of its state (the solver writes it; what acts on the body
// wakes it).
struct SleepState {
    std::vector<float> held_w;    // per particle: its inverse mass while its piece sleeps, else 0
    std::vector<Vec3f> anchor;    // per particle: where it was when its piece's still spell began
    std::vector<float> still;     // per piece: seconds it has been still
    std::vector<float> calm;      // per piece: seconds since it last moved faster than SleepSettings::speed
    size_t sleeping = 0;          // pieces asleep
    size_t movable = 0;           // pieces that can move at all (not static), asleep or awake
    bool judged = false;          // the pieces' kinds were read since the last wake (the counts hold)
    bool any() const { return sleeping > 0; }
    // Every piece that can move sleeps, or none can (a static body alone, a table with nothing
    // on it): a frame has nothing to do but watch for a wake.
    bool resting() const { return judged && sleeping == movable; }
};

// Every piece awake, its still spell begun again: called before anything acts on the body, so a
// cut copies true masses and a drag moves what it grabs.
template <class Real>
void wake_all(BodyStateT<Real>& state);

// Wakes the named pieces now, in the middle of a frame: a sleeping piece pressed harder than a
// resting contact presses (ContactSolver::pressed_sleepers). Held, it gave nothing, and a small
// piece pressed against it and its own constraints at once was answered by its light particles
// alone, sweep after sweep, and flung off at up to 50 m/s (docs/BENCHMARKS.md, "Contact").
template <class Real>
void wake_pieces(SoftBodyT<Real>& body, std::span<const uint32_t> pieces);

// After a frame of `dt`: updates the still spells from the particles' positions, puts the pieces
// still long enough to sleep and wakes those a moving piece touches. `touching`: pairs of pieces
// in contact (the contact search's candidates); pieces are the body's labels. `gives`: per piece,
// 1 where it answers contact particle by particle (a soft body): such a piece falls asleep only
// together with the awake pieces it touches. Pressed into a dent, it holds the piece on it up
// with a give that sleep would take away at once: a 5 kg ball resting on a soft box was flung
// 1.5 m/s up each time the box fell asleep under it (within a frame, its own shape pushing off
// the held dent), and bounced on it for ever. Stiff pieces barely give, and sleep one by one.
template <class Real>
void update_sleep(SoftBodyT<Real>& body, std::span<const std::pair<uint32_t, uint32_t>> touching, const SleepSettings& s, float dt,
                  std::span<const uint8_t> gives = {});

} // namespace pbdsplat::sim
