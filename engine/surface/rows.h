#pragma once
// Index lists by key in one array (compressed rows): the samples of each triangle, the
// triangles around each vertex. Built in two passes over the items, no allocation per key:
// the density control rebuilds them on every frame it works.
#include <cstdint>
#include <span>
#include <vector>

namespace pbdsplat::surface {

struct Rows {
    std::vector<uint32_t> start, items;  // keys [0, n): items[start[k], start[k + 1]), in insertion order
    std::span<const uint32_t> operator[](uint32_t k) const { return {items.data() + start[k], items.data() + start[k + 1]}; }
};

// Items [0, count) by key_of(i) in [0, keys); include(i) false leaves an item out.
template <class KeyOf, class Include>
Rows make_rows(size_t keys, size_t count, const KeyOf& key_of, const Include& include) {
    Rows r;
    r.start.assign(keys + 1, 0);
    for (size_t i = 0; i < count; ++i)
        if (include(i)) ++r.start[key_of(i) + 1];
    for (size_t k = 0; k < keys; ++k) r.start[k + 1] += r.start[k];
    r.items.resize(r.start.back());
    std::vector<uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (size_t i = 0; i < count; ++i)
        if (include(i)) r.items[fill[key_of(i)]++] = uint32_t(i);
    return r;
}
template <class KeyOf>
Rows make_rows(size_t keys, size_t count, const KeyOf& key_of) {
    return make_rows(keys, count, key_of, [](size_t) { return true; });
}

// The triangles around each vertex: corner c = 3 t + k of triangle t lists under its vertex.
template <class Triangles>
Rows corner_rows(size_t vertices, const Triangles& triangles) {
    return make_rows(vertices, triangles.size() * 3, [&](size_t c) { return triangles[c / 3][c % 3]; });
}

} // namespace pbdsplat::surface
