#include "sim/state_hash.h"

#include <cstring>

namespace pbdsplat::sim {

uint64_t state_hash(const Particles& p) {
    uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* data, size_t bytes) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    for (size_t i = 0; i < p.size(); ++i) {
        mix(p.x[i].data(), sizeof(float) * 3);
        mix(p.v[i].data(), sizeof(float) * 3);
    }
    return h;
}

} // namespace pbdsplat::sim
