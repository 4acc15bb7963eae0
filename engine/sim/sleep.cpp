#include "sim/sleep.h"

#include <algorithm>
#include <span>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

namespace {
// The per-particle and per-piece arrays sized to the body as it is now: a topology edit appends
// particles and pieces (awake: whatever acts on the body wakes it first).
template <class Real>
void fit_to(SleepState& st, const SoftBodyT<Real>& body) {
    const size_t n = body.particle_count();
    st.held_w.resize(n, 0.0f);
    st.anchor.reserve(n);
    while (st.anchor.size() < n) st.anchor.push_back(xyz(body.particles.x[st.anchor.size()]));
    st.anchor.resize(n);
    st.still.resize(body.pieces, 0.0f);
    st.calm.resize(body.pieces, 0.0f);
}

constexpr uint8_t k_static = 0, k_awake_still = 1, k_awake_moving = 2, k_sleeping = 3;

// Per piece, the lowest piece it is welded to through any chain of live welds (itself where it
// has none): welded pieces sleep and wake as one. A leg asleep under a table top still settling
// held its end of the welds and the top's shape cluster still, while the rest pulled on it: the
// table flew apart at 100 m/s within a second of its legs falling asleep.
template <class Real>
std::vector<uint32_t> weld_groups(const SoftBodyT<Real>& body) {
    std::vector<uint32_t> up(body.pieces);
    for (uint32_t k = 0; k < up.size(); ++k) up[k] = k;
    const auto root = [&](uint32_t k) {
        while (up[k] != k) k = up[k] = up[up[k]];
        return k;
    };
    for (const DistanceConstraint& w : body.welds) {
        if (!w.alive() || w.i >= body.piece_of_particle.size() || w.j >= body.piece_of_particle.size()) continue;
        const uint32_t a = body.piece_of_particle[w.i], b = body.piece_of_particle[w.j];
        if (a >= up.size() || b >= up.size()) continue;
        const uint32_t ra = root(a), rb = root(b);
        if (ra != rb) up[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (uint32_t k = 0; k < up.size(); ++k) up[k] = root(k);
    return up;
}
} // namespace

template <class Real>
void wake_all(BodyStateT<Real>& state) {
    SleepState& st = state.sleep;
    ParticlesT<Real>& p = state.particles;
    if (st.sleeping > 0)
        for (size_t i = 0; i < st.held_w.size() && i < p.size(); ++i)
            if (st.held_w[i] > 0.0f) p.w[i] = Real(st.held_w[i]), st.held_w[i] = 0.0f;
    std::fill(st.still.begin(), st.still.end(), 0.0f);
    std::fill(st.calm.begin(), st.calm.end(), 0.0f);
    st.anchor.resize(std::min(st.anchor.size(), p.size()));
    for (size_t i = 0; i < st.anchor.size(); ++i) st.anchor[i] = xyz(p.x[i]);
    st.sleeping = 0;
    st.movable = 0;
    st.judged = false;
}

namespace {
// Gives particle i back the mass it had when its piece fell asleep; its still spell begins where
// it is now.
template <class Real>
void release(ParticlesT<Real>& p, SleepState& st, size_t i) {
    if (st.held_w[i] > 0.0f) p.w[i] = Real(st.held_w[i]);
    st.held_w[i] = 0.0f;
    st.anchor[i] = xyz(p.x[i]);
}
} // namespace

template <class Real>
void wake_pieces(SoftBodyT<Real>& body, std::span<const uint32_t> pieces) {
    SleepState& st = body.sleep;
    if (pieces.empty() || st.sleeping == 0) return;
    constexpr uint8_t asked = 1, woken = 2;
    std::vector<uint8_t> wake(body.pieces, 0);
    std::vector<uint8_t> group_asked(body.pieces, 0);
    const std::vector<uint32_t> group = weld_groups(body);
    for (uint32_t k : pieces)
        if (k < wake.size()) group_asked[group[k]] = 1;
    for (uint32_t k = 0; k < wake.size(); ++k)
        if (group_asked[group[k]]) wake[k] = asked;
    for (size_t i = 0; i < st.held_w.size() && i < body.particles.size(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k >= wake.size() || wake[k] == 0 || !(st.held_w[i] > 0.0f)) continue;
        release(body.particles, st, i);
        wake[k] = woken;
    }
    for (uint32_t k = 0; k < wake.size(); ++k)
        if (wake[k] == woken) {
            if (k < st.still.size()) st.still[k] = 0.0f;
            st.sleeping -= st.sleeping > 0 ? 1 : 0;
        }
}

namespace {
// Each piece's kind this frame: static (nothing in it can move), asleep, still or moving. Sleep
// is read off the particles (a held mass), so it follows a piece through relabelling.
template <class Real>
std::vector<uint8_t> piece_kinds(const SoftBodyT<Real>& body, const SleepState& st, const SleepSettings& s, std::vector<uint8_t>& fast) {
    const ParticlesT<Real>& p = body.particles;
    const size_t pieces = body.pieces;
    const float edge = float(body.distance_groups.mean_rest());
    const float drift = s.drift * edge, reach = s.radius * edge;
    std::vector<uint8_t> kind(pieces, k_static);
    const float limit = s.speed * edge;
    fast.assign(pieces, 0);
    std::vector<Vec3f> shift(pieces, Vec3f::Zero());  // the free particles' mean way from their anchors
    std::vector<float> speed2(pieces, 0.0f);         // and their squared speeds' sum
    std::vector<uint32_t> count(pieces, 0);
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k >= pieces || kind[k] == k_sleeping) continue;
        if (st.held_w[i] > 0.0f) {
            kind[k] = k_sleeping;
        } else if (p.w[i] > Real(0)) {
            const Vec3f d = xyz(p.x[i]) - st.anchor[i];
            shift[k] += d, speed2[k] += float(p.v[i].squaredNorm()), ++count[k];
            kind[k] = d.squaredNorm() > reach * reach ? k_awake_moving : std::max(kind[k], k_awake_still);
        }
    }
    for (uint32_t k = 0; k < pieces; ++k) {
        if (kind[k] != k_awake_still && kind[k] != k_awake_moving) continue;
        const float n = float(count[k]);
        fast[k] = speed2[k] / n > limit * limit;
        if (kind[k] == k_awake_still && ((shift[k] / n).squaredNorm() > drift * drift || fast[k])) kind[k] = k_awake_moving;
    }
    // A leaking piece changes by itself: it never sleeps.
    for (const VolumeConstraint& v : body.volumes)
        if (v.leak > 0.0f && v.piece < pieces && kind[v.piece] != k_static) kind[v.piece] = k_awake_moving;
    return kind;
}

constexpr uint8_t k_stays = 0, k_falls_asleep = 1, k_wakes = 2;

// Holds the particles of the pieces that fall asleep and frees those of the pieces that wake; a
// piece that moved begins its still spell where it is now.
template <class Real>
void apply(SoftBodyT<Real>& body, SleepState& st, std::span<const uint8_t> kind, std::span<const uint8_t> change) {
    ParticlesT<Real>& p = body.particles;
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k >= kind.size()) continue;
        if (change[k] == k_falls_asleep && p.w[i] > Real(0)) {
            st.held_w[i] = float(p.w[i]);
            p.w[i] = Real(0), p.v[i].setZero(), p.x_prev[i] = p.x[i];
        } else if (change[k] == k_wakes) {
            release(p, st, i);
        } else if (kind[k] == k_awake_moving) {
            st.anchor[i] = xyz(p.x[i]);
        }
    }
    st.sleeping = 0, st.movable = 0, st.judged = true;
    for (size_t k = 0; k < kind.size(); ++k) {
        st.movable += kind[k] != k_static ? 1 : 0;
        if (change[k] == k_wakes) st.still[k] = 0.0f;
        const bool asleep = kind[k] == k_sleeping ? change[k] != k_wakes : change[k] == k_falls_asleep;
        st.sleeping += asleep ? 1 : 0;
    }
}
} // namespace

namespace {
// Welded pieces as one: a group sleeps only when every awake piece of it falls asleep, and wakes
// whole when any piece of it wakes or moves.
void join_welded(std::span<const uint32_t> group, std::span<const uint8_t> kind, std::vector<uint8_t>& change) {
    const size_t pieces = change.size();
    std::vector<uint8_t> stays_awake(pieces, 0), wakes(pieces, 0);
    for (uint32_t k = 0; k < pieces; ++k) {
        const bool awake = kind[k] == k_awake_still || kind[k] == k_awake_moving;
        if (awake && change[k] != k_falls_asleep) stays_awake[group[k]] = 1;
        if (change[k] == k_wakes) wakes[group[k]] = 1;
    }
    for (uint32_t k = 0; k < pieces; ++k) {
        const uint32_t g = group[k];
        if (kind[k] == k_sleeping && (wakes[g] || stays_awake[g])) change[k] = k_wakes;
        else if (change[k] == k_falls_asleep && (stays_awake[g] || wakes[g])) change[k] = k_stays;
    }
}

// A giving piece about to fall asleep stays awake while a piece it touches stays awake (through
// chains of such pieces: each pass settles one more link).
void hold_giving_awake(std::span<const std::pair<uint32_t, uint32_t>> touching, std::span<const uint8_t> gives, std::span<const uint8_t> kind,
                       std::vector<uint8_t>& change) {
    const size_t pieces = change.size();
    const auto stays_awake = [&](uint32_t k) {
        const bool awake = kind[k] == k_awake_still || kind[k] == k_awake_moving;
        return (awake && change[k] != k_falls_asleep) || change[k] == k_wakes;
    };
    const auto held = [&](uint32_t k, uint32_t other) { return k < gives.size() && gives[k] && change[k] == k_falls_asleep && stays_awake(other); };
    for (bool again = true; again;) {
        again = false;
        for (const auto& [a, b] : touching) {
            if (a >= pieces || b >= pieces) continue;
            if (held(a, b)) change[a] = k_stays, again = true;
            if (held(b, a)) change[b] = k_stays, again = true;
        }
    }
}
} // namespace

template <class Real>
void update_sleep(SoftBodyT<Real>& body, std::span<const std::pair<uint32_t, uint32_t>> touching, const SleepSettings& s, float dt,
                  std::span<const uint8_t> gives) {
    SleepState& st = body.sleep;
    if (!s.enabled) {
        if (st.any()) wake_all<Real>(body);
        return;
    }
    fit_to(st, body);
    const size_t pieces = body.pieces;
    std::vector<uint8_t> fast;
    const std::vector<uint8_t> kind = piece_kinds(body, st, s, fast);
    for (uint32_t k = 0; k < pieces; ++k) {
        if (kind[k] == k_awake_moving) st.still[k] = 0.0f;
        else if (kind[k] == k_awake_still) st.still[k] += dt;
        st.calm[k] = fast[k] ? 0.0f : st.calm[k] + dt;
    }
    // A piece still long enough falls asleep; a sleeping piece wakes when a piece touching it
    // moves (one dropped onto it, or what it rests on sliding away).
    std::vector<uint8_t> change(pieces, k_stays);
    for (uint32_t k = 0; k < pieces; ++k)
        if ((kind[k] == k_awake_still || kind[k] == k_awake_moving) && st.still[k] >= s.time) change[k] = k_falls_asleep;
    // It stays awake while a piece touching it moved fast within a still spell's time: held under
    // a piece bouncing on it, it would give nothing at the bounce's turn and fling it off.
    const auto restless = [&](uint32_t k) { return (kind[k] == k_awake_still || kind[k] == k_awake_moving) && st.calm[k] < s.time; };
    for (const auto& [a, b] : touching) {
        if (a >= pieces || b >= pieces) continue;
        if (kind[a] == k_sleeping && kind[b] == k_awake_moving) change[a] = k_wakes;
        if (kind[b] == k_sleeping && kind[a] == k_awake_moving) change[b] = k_wakes;
        if (change[a] == k_falls_asleep && restless(b)) change[a] = k_stays;
        if (change[b] == k_falls_asleep && restless(a)) change[b] = k_stays;
    }
    if (!gives.empty()) hold_giving_awake(touching, gives, kind, change);
    if (!body.welds.empty()) join_welded(weld_groups(body), kind, change);
    apply(body, st, kind, change);
}

template void wake_all<float>(BodyStateT<float>&);
template void wake_all<double>(BodyStateT<double>&);
template void wake_pieces<float>(SoftBodyT<float>&, std::span<const uint32_t>);
template void wake_pieces<double>(SoftBodyT<double>&, std::span<const uint32_t>);
template void update_sleep<float>(SoftBodyT<float>&, std::span<const std::pair<uint32_t, uint32_t>>, const SleepSettings&, float, std::span<const uint8_t>);
template void update_sleep<double>(SoftBodyT<double>&, std::span<const std::pair<uint32_t, uint32_t>>, const SleepSettings&, float, std::span<const uint8_t>);

} // namespace pbdsplat::sim
