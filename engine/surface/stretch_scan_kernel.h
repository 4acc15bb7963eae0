// The stretch scan's one body, compiled once per lane width: stretch_scan.cpp includes it
// inside `stretch_scan_lanes::four` and `stretch_scan_lanes::eight`, each of which defines the
// register type V, k_lanes, the lane operations (PBDSPLAT_LANE_OPERATIONS) and the two loads
// whose shuffles differ by width (load_edges, load_rest). No include guard: it is meant to be
// included twice. No fused multiply-add: both widths must round alike, to the bit.

// u . v over three rows of lanes.
inline V dot3(const V* u, const V* v) { return add(add(mul(u[0], v[0]), mul(u[1], v[1])), mul(u[2], v[2])); }

// (p, q) G (p, q)^T, G = [g11 g12; g12 g22], lane by lane.
inline V form(V p, V q, V g11, V g12, V g22) {
    return add(add(mul(mul(p, p), g11), mul(mul(set1(2.0f), mul(p, q)), g12)), mul(mul(q, q), g22));
}

// mesh::squared_stretches in k_lanes lanes from triangle `begin` (a multiple of four), the
// thresholds tested in the same lanes: a lane where nothing changed by 5 %, nothing is past a
// threshold and nothing was is quiet, and skips the per-triangle logic. Returns where it stopped.
inline size_t scan(const StretchScan& s, size_t begin, std::vector<uint32_t>& busy) {
    const V v_grow2 = set1(s.grow2), v_shrink2 = set1(s.shrink2);
    const V v_squash2 = set1(s.squash2), v_unsquash2 = set1(s.unsquash2);
    const V v_tiny = set1(1e-12f), v_zero = set1(0.0f), v_half = set1(0.5f);
    const size_t n = s.triangles.size();
    size_t t = begin;
    for (; t + k_lanes <= n; t += k_lanes) {
        V e1[4], e2[4];
        load_edges(s, t, e1, e2);
        V a, c, b, d;
        load_rest(s.rest_lanes + 4 * t, a, c, b, d);
        const V g11 = dot3(e1, e1), g12 = dot3(e1, e2), g22 = dot3(e2, e2);
        const V p11 = form(a, c, g11, g12, g22), p22 = form(b, d, g11, g12, g22);
        const V p12 = add(add(mul(mul(a, b), g11), mul(add(mul(a, d), mul(b, c)), g12)), mul(mul(c, d), g22));
        const V half = mul(v_half, add(p11, p22)), diff = mul(v_half, sub(p11, p22));
        const V root = square_root(add(mul(diff, diff), mul(p12, p12)));
        const V l2 = add(half, root), s2 = maximum(sub(half, root), v_zero);
        store(s.stretch2 + t, l2);
        store(s.squeeze2 + t, s2);
        const V ref2 = load(s.reference2 + t);
        const V ref_squeeze2 = maximum(load(s.reference_squeeze2 + t), v_tiny);
        V any = either(less(l2, load(s.shrank_large2 + t)), less(s2, load(s.shrank_small2 + t)));
        any = either(any, either(greater(l2, load(s.grew_large2 + t)), greater(s2, load(s.grew_small2 + t))));
        any = either(any, either(greater(l2, mul(v_grow2, ref2)), greater(s2, mul(v_unsquash2, ref_squeeze2))));
        any = either(any, either(less(l2, mul(v_shrink2, ref2)), less(s2, mul(v_squash2, ref_squeeze2))));
        // NaN (a broken simulation) compares false everywhere: take the per-triangle path too.
        any = either(any, unordered(l2, s2));
        append(busy, t, lane_mask(any) | counting(s.beyond + t, k_lanes));
    }
    return t;
}
