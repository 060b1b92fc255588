// The octree's walk (octree.cpp), which includes this file twice: in namespace oct_sse for any
// x86-64, and in oct_avx2 with PCRT_OCT_WALK_TARGET the attribute target("avx2") on every function
// (empty in oct_sse), with kWalkAvx2 set before each.
// Before, a generic walk was inlined into one AVX2 entry point; GCC inlines no target("avx2")
// function into a generic one, so the AVX2 child test (cells_and_boxes_avx2) stayed a call per
// inner node. Compiled for AVX2 as a whole it inlines, and `flatten` on walk inlines the rest
// (RaySlabs, the root's box, Eigen's small-vector code: GCC's heuristics left those as calls in
// an AVX2 function, and the walk then ran 8-13% slower than before instead of faster). Measured
// in results/anchor/oct_flat. No include guard and no includes: it reads octree.cpp's types.

// The ray interval whose crossings a leaf may report: its cell's, from hits_before_leaf before
// it (crossings before tmin are no hits), widened by the gap rounding may leave between two
// cells' intervals. A wall shared by cells of different depths is summed from the root in
// different orders (up to max_depth half-ulps of its coordinate each), which in t is divided by
// the ray's direction along it: a crossing in such a gap is a hit the nearest-disc methods report
// from the leaf before it (inv_max: the largest |1 / d_a|; infinite keeps every leaf).
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline std::pair<float, float> slab_interval(
    const OctWalkData& w, const OctTodo& cur, const Ray& ray, float inv_max) {
  const float gap = 4e-6f * (cur.lo.cwiseAbs().maxCoeff() + cur.side) * inv_max;
  return {std::max(cur.t0 - w.hits_before_leaf - gap, ray.tmin), cur.t1 + gap};
}

// Narrows [near, far] to the ray's interval in box q of the cell at lo (quantum: cell_quantum
// of its side), as slab_axis_sse does; false when the ray misses the box or it is empty.
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline bool narrow_to_box(
    const CellBox& q, const Vec3& lo, float quantum, const RaySlabs& r, float& near, float& far) {
  if (q.empty()) return false;
  for (int a = 0; a < 3; ++a) {
    const float blo = lo[a] + quantum * kByteFloat[q.lo[size_t(a)]];
    const float bhi = lo[a] + quantum * kByteFloat[q.hi[size_t(a)]];
    const float tn = ((r.neg[a] ? bhi : blo) - r.o[a]) * r.inv[a];
    const float tf = ((r.neg[a] ? blo : bhi) - r.o[a]) * r.inv[a] * kWiden;
    near = tn > near ? tn : near;  // NaN (0 * inf) keeps the interval
    far = tf < far ? tf : far;
  }
  return near <= far;
}

// The items of leaf n: a piece of the references, or its compact references decoded into
// `decoded`.
template <class N>
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline std::span<const uint32_t> leaf_items(
    const OctWalkData& w, const N& n, std::array<uint32_t, kOctCompactMax>& decoded) {
  if (!n.compact()) return {w.refs + n.first(), n.leaf_count()};
  const uint16_t* r = w.refs16 + n.first();
  const uint32_t base = uint32_t(r[0]) | uint32_t(r[1]) << 16;
  for (uint32_t k = 0; k < n.leaf_count(); ++k) decoded[k] = base + r[2 + k];
  return {decoded.data(), n.leaf_count()};
}

// The children of `hit` (not 0) into order, bottom of the stack to top: far to near (ties: the
// lower child on top), or for kAny in child order; returns how many. Two children are ordered by
// a select, not a branch: which of two entries is nearer is a coin toss the branch predictor
// loses half the time (that comparison was the walk's hottest branch in a profile on the tile).
template <bool kAny>
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline int sort_children(
    uint32_t hit, const float* nears, std::array<uint32_t, 8>& order) {
  const auto c0 = uint32_t(__builtin_ctz(hit));
  const uint32_t rest = hit & (hit - 1);
  if (rest == 0) {
    order[0] = c0;
    return 1;
  }
  const auto c1 = uint32_t(__builtin_ctz(rest));
  if ((rest & (rest - 1)) == 0) {
    const bool c0_on_top = !kAny && nears[c0] <= nears[c1];
    order[0] = c0_on_top ? c1 : c0;
    order[1] = c0_on_top ? c0 : c1;
    return 2;
  }
  int m = 0;
  for (uint32_t mask = hit; mask; mask &= mask - 1) {
    const auto c = uint32_t(__builtin_ctz(mask));
    int j = m++;
    if constexpr (!kAny)
      for (; j > 0 && nears[order[size_t(j - 1)]] <= nears[c]; --j)
        order[size_t(j)] = order[size_t(j - 1)];
    order[size_t(j)] = c;
  }
  return m;
}

// The stored children of a cell at lo (children of side `half`) that the ray crosses: a bit per
// child, their cells' intervals in t0s and t1s and where the ray enters their boxes in nears
// (the cells' entries without kept boxes). Empty leaves too: the pop reads a node anyway, and
// reading each child here to skip them was a cache miss per child pushed (9% of the walk).
template <bool kBoxes, class N>
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline uint32_t child_tests(
    const OctWalkData& w, const N& n, const Vec3& lo, float half, const RaySlabs& slabs, float tmax,
    float* t0s, float* t1s, float* nears) {
  const uint32_t children = n.child_mask();
  const GroupBoxes group{kBoxes ? w.boxes + 6 * size_t(n.first()) : nullptr,
                         uint32_t(kBitsSet[children])};  // unread without boxes
  if constexpr (kWalkAvx2 && kBoxes)
    return cells_and_boxes_avx2(children, group, lo, half, slabs, tmax, t0s, t1s, nears);
  uint32_t hit = children;
  if constexpr (kWalkAvx2) {
    hit &= octant_test_avx2(lo, half, slabs, tmax, t0s, t1s);
  } else {
    hit &= octant_test_sse(lo, half, slabs, tmax, t0s, t1s);
  }
  if constexpr (!kBoxes) {
    std::memcpy(nears, t0s, 8 * sizeof(float));
    return hit;
  }
  const float quantum = cell_quantum(half);
  for (uint32_t mask = hit; mask; mask &= mask - 1) {
    const auto c = uint32_t(__builtin_ctz(mask));
    const Vec3 clo = lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
    float far = t1s[c];
    nears[c] = t0s[c];
    if (!narrow_to_box(group.box(kRankOf[children][c]), clo, quantum, slabs, nears[c], far))
      hit &= ~(1u << c);
  }
  return hit;
}

// The children of `n` (the node of `cur`) that the ray crosses, in the order a stack pops them:
// near to far (ties: the lower child first), or for kAny in reverse child order (any blocker
// ends an occlusion query and an unblocked ray visits every cell it crosses anyway). The first
// replaces `cur`, the others are pushed; false if there are none. The eight child cubes are
// tested at once (octant_test_*: AVX2 or SSE), as the bvh tests its wide nodes, and then the
// crossed children's boxes, if kept (child_tests).
template <bool kAny, bool kBoxes, class N>
PCRT_OCT_WALK_TARGET __attribute__((always_inline)) inline bool next_children(
    const OctWalkData& w, const N& n, const RaySlabs& slabs, float tmax, OctTodo* stack, int& top,
    OctTodo& cur) {
  const float half = 0.5f * cur.side;
  const Vec3 lo = cur.lo;
  alignas(32) float t0s[8], t1s[8], nears[8];
  const uint32_t hit = child_tests<kBoxes>(w, n, lo, half, slabs, tmax, t0s, t1s, nears);
  if (hit == 0) return false;
  // Bottom of the stack to top: far to near (a ray crosses at most 4), else child order.
  std::array<uint32_t, 8> order;
  const int m = sort_children<kAny>(hit, nears, order);
  const uint32_t children = n.child_mask();
  const auto first = uint32_t(n.first());
  for (int k = 0; k < m; ++k) {
    const uint32_t c = order[size_t(k)];
    const Vec3 clo = lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
    const OctTodo x{first + kRankOf[children][c], clo, half, nears[c], t0s[c], t1s[c]};
    if (k + 1 < m) {
      stack[top++] = x;
    } else {
      cur = x;
    }
  }
  return true;
}

// The walk over nodes (OctNode32 or OctNode64). kAny: an occlusion query, ended by the first
// leaf that reports a hit; `hit.t` is then the ray's tmax. kBoxes: the nodes keep child boxes
// (w.boxes is not null).
template <bool kAny, bool kBoxes, class N>
PCRT_OCT_WALK_TARGET __attribute__((flatten)) bool walk(const OctWalkData& w, const N* nodes,
                                                        const Ray& ray, const LeafIntersector& leaf,
                                                        Hit& hit, OpCounters& counters) {
  if (w.items == 0) return false;
  const Vec3 inv = ray.d.cwiseInverse();
  const RaySlabs slabs(ray);
  const float inv_max = inv.cwiseAbs().maxCoeff();  // for slab_interval
  std::array<OctTodo, 8 * 32> stack;  // at most 7 siblings waiting per level, max_depth <= 30
  std::array<uint32_t, kOctCompactMax> decoded;
  int top = 0;
  float t0 = 0, t1 = 0;
  if (!Aabb{w.root_lo, w.root_lo + Vec3::Constant(w.root_side)}.intersect(ray, inv, t0, t1))
    return false;
  float near = t0, far = t1;
  if (kBoxes && !narrow_to_box(GroupBoxes{w.boxes, 1}.box(0), w.root_lo, cell_quantum(w.root_side),
                               slabs, near, far))
    return false;
  // The next node to visit stays out of the stack: reading back a Todo just written piecewise
  // stalled store forwarding (15% of the walk).
  OctTodo cur{0, w.root_lo, w.root_side, near, t0, t1};
  bool found = false;
  while (true) {
    if (may_improve(cur.near, hit.t)) {
      const N& n = nodes[cur.node];
      if (n.count != 0) {  // else a leaf the disc planes all missed (inner nodes count > 0)
        counters.add(kNodesVisited);
        if (!n.leaf()) {
          if (next_children<kAny, kBoxes>(w, n, slabs, ray.tmax, stack.data(), top, cur)) continue;
        } else if (!n.has_slab() ||
                   crosses_slab(w.disc_slabs[cur.node], ray, slab_interval(w, cur, ray, inv_max))) {
          counters.add(kLeavesVisited);
          counters.add(kItemsVisited, n.leaf_count());
          const LeafVisit visit{leaf_items(w, n, decoded), cur.t0, cur.t1};
          if constexpr (kAny) {
            if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
          } else {
            found |= leaf.intersect_leaf(ray, visit, hit, counters);
          }
        }
      }
    } else if constexpr (!kAny) {
      break;  // disjoint cells in depth-first order: the rest is further
    }         // kAny: pushed in child order, only this cell is beyond
    if (top == 0) break;
    cur = stack[size_t(--top)];
  }
  return found;
}
