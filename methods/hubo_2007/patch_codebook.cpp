#include "methods/hubo_2007/patch_codebook.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace pcrt {
namespace {

constexpr int kCells = 16;  // PatchCodebook::kGrid squared
// The shape descriptor: mean height per cell, then the fraction of the points per cell (patches
// with the same heights but another footprint, e.g. a strip along an edge, are not alike).
constexpr int kDims = 2 * kCells;
using Descriptor = std::array<float, kDims>;
constexpr float kTurn = 6.28318530717958f;

float sign_of(float v) { return v < 0 ? -1.0f : 1.0f; }

uint16_t unit16(float x) {  // [-1, 1] to 16 bits
  return uint16_t(std::lround(std::clamp((x + 1) * 0.5f, 0.0f, 1.0f) * 65535.0f));
}
float from16(uint16_t q) { return float(q) * (2.0f / 65535.0f) - 1.0f; }

void encode_octahedral(const Vec3& n, uint16_t& qu, uint16_t& qv) {
  const float l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
  float u = l1 > 0 ? n.x() / l1 : 0, v = l1 > 0 ? n.y() / l1 : 0;
  if (n.z() < 0) {
    const float fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
    u = fu, v = fv;
  }
  qu = unit16(u), qv = unit16(v);
}
Vec3 decode_octahedral(uint16_t qu, uint16_t qv) {
  float u = from16(qu), v = from16(qv);
  const float z = 1.0f - std::abs(u) - std::abs(v);
  if (z < 0) {
    const float fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
    u = fu, v = fv;
  }
  return Vec3(u, v, z).normalized();
}

// The patch frame: normal n, in-plane axes u (at `angle` of a turn from a basis fixed by n), v.
struct Frame {
  Vec3 n, u, v;
};
Frame frame(const Vec3& n, uint16_t angle) {
  const Vec3 t1 = (std::abs(n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 t2 = n.cross(t1);
  const float a = float(angle) * (kTurn / 65536.0f);
  const Vec3 u = std::cos(a) * t1 + std::sin(a) * t2;
  return {n, u, n.cross(u)};
}

int cell_of(float x, float y) {
  constexpr int g = 4;
  const int ix = std::clamp(int((x + 1) * 0.5f * g), 0, g - 1);
  const int iy = std::clamp(int((y + 1) * 0.5f * g), 0, g - 1);
  return iy * g + ix;
}

// Mean height per cell of local points (0 where a cell has none) and the fraction of the points
// in each cell; `filled` says which cells had points.
template <typename Points>
Descriptor heights(const Points& pts, std::array<bool, kCells>* filled = nullptr) {
  Descriptor sum{};
  std::array<int, kCells> count{};
  for (const auto& p : pts) {
    const int c = cell_of(p.x, p.y);
    sum[c] += p.z;
    ++count[c];
  }
  const float n = std::max<float>(1.0f, float(std::size(pts)));
  for (int c = 0; c < kCells; ++c) {
    sum[c] = count[c] ? sum[c] / float(count[c]) : 0.0f;
    sum[kCells + c] = float(count[c]) / n;
    if (filled) (*filled)[c] = count[c] > 0;
  }
  return sum;
}

float distance2(const Descriptor& a, const Descriptor& b) {
  float d = 0;
  for (int c = 0; c < kDims; ++c) d += (a[c] - b[c]) * (a[c] - b[c]);
  return d;
}

// k-means (Lloyd's iterations) on the height fields, started from every (P/K)-th patch: a label
// per patch in 0..K-1, K = min(clusters, patches).
std::vector<uint32_t> cluster(const std::vector<Descriptor>& desc, size_t clusters, int iterations,
                              OpCounters& counters) {
  const size_t np = desc.size(), nk = std::max<size_t>(1, std::min(clusters, np));
  std::vector<uint32_t> label(np, 0);
  if (np == 0) return label;
  std::vector<Descriptor> mean(nk);
  for (size_t j = 0; j < nk; ++j) mean[j] = desc[j * np / nk];
  for (int it = 0; it < iterations; ++it) {
    tbb::parallel_for(size_t(0), np, [&](size_t k) {
      float best = kInfinity;
      for (size_t j = 0; j < nk; ++j) {
        const float d = distance2(desc[k], mean[j]);
        if (d < best) best = d, label[k] = uint32_t(j);
      }
    });
    std::vector<Descriptor> sum(nk, Descriptor{});
    std::vector<size_t> count(nk, 0);
    for (size_t k = 0; k < np; ++k) {
      for (int c = 0; c < kDims; ++c) sum[label[k]][c] += desc[k][c];
      ++count[label[k]];
    }
    for (size_t j = 0; j < nk; ++j)
      if (count[j] > 0)
        for (int c = 0; c < kDims; ++c) mean[j][c] = sum[j][c] / float(count[j]);
  }
  counters.add(kCodebookKmeansTerms, np * nk * size_t(iterations));
  return label;
}

}  // namespace

// The patch's frame and scale into its instance, its points in that frame into `local`; returns
// its height field. The frame is taken from the quantized normal and angle, so that decoding
// rebuilds exactly the frame the points were expressed in.
Descriptor encode_frame(std::span<const PackedSplat> points, const PatchInput& patch,
                        PatchCodebook::Instance& inst, std::span<PatchCodebook::LocalPoint> local) {
  encode_octahedral(patch.normal, inst.normal_u, inst.normal_v);
  const Frame base = frame(decode_octahedral(inst.normal_u, inst.normal_v), 0);
  float a = 0, b = 0, c = 0, scale = 0, nearest = kInfinity;
  for (uint32_t i = patch.begin; i < patch.end; ++i) {
    const Vec3 d = points[i].c - patch.centre;
    const float x = d.dot(base.u), y = d.dot(base.v);
    a += x * x, b += x * y, c += y * y;
    scale = std::max(scale, d.norm());
    if (d.squaredNorm() < nearest) nearest = d.squaredNorm(), inst.prim = points[i].index;
  }
  // The in-plane axis of largest spread, signed so the points' third moment along it is >= 0.
  float theta = 0.5f * std::atan2(2 * b, a - c);
  float skew = 0;
  const Vec3 u0 = std::cos(theta) * base.u + std::sin(theta) * base.v;
  for (uint32_t i = patch.begin; i < patch.end; ++i)
    skew += std::pow((points[i].c - patch.centre).dot(u0), 3.0f);
  if (skew < 0) theta += 0.5f * kTurn;
  const float turns = theta / kTurn;
  inst.angle = uint16_t(std::lround((turns - std::floor(turns)) * 65536.0f) & 0xffff);
  inst.scale = std::max(scale, 1e-30f);
  const Frame f = frame(base.n, inst.angle);
  for (uint32_t i = patch.begin; i < patch.end; ++i) {
    const Vec3 d = (points[i].c - patch.centre) / inst.scale;
    const Vec3& n = points[i].n;
    local[i] = {d.dot(f.u), d.dot(f.v), d.dot(f.n), n.dot(f.u), n.dot(f.v), n.dot(f.n)};
  }
  return heights(local.subspan(patch.begin, patch.end - patch.begin));
}

void PatchCodebook::build(std::span<const PackedSplat> points, std::span<const PatchInput> patches,
                          size_t clusters, int iterations, OpCounters& counters) {
  const size_t np = patches.size();
  instances_.assign(np, Instance{});
  std::vector<LocalPoint> local(points.size());
  std::vector<Descriptor> desc(np);
  tbb::parallel_for(size_t(0), np, [&](size_t k) {
    desc[k] = encode_frame(points, patches[k], instances_[k], local);
  });
  const std::vector<uint32_t> label = cluster(desc, clusters, iterations, counters);
  // Each cluster's representative: its member nearest the cluster's mean height field.
  const size_t nk = label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1;
  std::vector<Descriptor> mean(nk, Descriptor{});
  std::vector<size_t> members(nk, 0);  // the final assignment's means
  for (size_t k = 0; k < np; ++k) {
    for (int c = 0; c < kDims; ++c) mean[label[k]][c] += desc[k][c];
    ++members[label[k]];
  }
  std::vector<uint32_t> rep(nk, UINT32_MAX);
  std::vector<float> best(nk, kInfinity);
  for (size_t k = 0; k < np; ++k) {
    const size_t j = label[k];
    Descriptor m = mean[j];
    for (float& x : m) x /= float(members[j]);
    const float d = distance2(desc[k], m);
    if (d < best[j]) best[j] = d, rep[j] = uint32_t(k);
  }
  std::vector<uint32_t> id(nk, UINT32_MAX);
  rep_begin_.assign(1, 0);
  rep_points_.clear();
  for (size_t j = 0; j < nk; ++j) {
    if (rep[j] == UINT32_MAX) continue;
    id[j] = uint32_t(rep_begin_.size() - 1);
    const PatchInput& p = patches[rep[j]];
    rep_points_.insert(rep_points_.end(), local.begin() + p.begin, local.begin() + p.end);
    rep_begin_.push_back(uint32_t(rep_points_.size()));
  }
  tbb::parallel_for(size_t(0), np,
                    [&](size_t k) { set_residual(k, id[label[k]], patches[k], local); });
}

// The representative's heights moved onto the patch's own, cell by cell where both have points.
void PatchCodebook::set_residual(size_t k, uint32_t rep, const PatchInput& p,
                                 std::span<const LocalPoint> local) {
  Instance& in = instances_[k];
  in.cluster = uint16_t(rep);
  std::array<bool, kCells> own_filled{}, rep_filled{};
  const Descriptor own = heights(local.subspan(p.begin, p.end - p.begin), &own_filled);
  const Descriptor r = heights(std::span<const LocalPoint>(rep_points_)
                                   .subspan(rep_begin_[rep], rep_begin_[rep + 1] - rep_begin_[rep]),
                               &rep_filled);
  in.footprint = 0;
  for (int c = 0; c < kCells; ++c) {
    const float q = std::clamp(std::round((own[c] - r[c]) * 127.0f), -127.0f, 127.0f);
    in.residual[c] = own_filled[c] && rep_filled[c] ? int8_t(q) : int8_t(0);
    if (own_filled[c]) in.footprint |= uint16_t(1u << c);
  }
}

void PatchCodebook::decode(uint32_t k, const Vec3& centre, std::vector<PackedSplat>& out,
                           OpCounters& counters) const {
  const Instance& in = instances_[k];
  const Frame f = frame(decode_octahedral(in.normal_u, in.normal_v), in.angle);
  const uint32_t b = rep_begin_[in.cluster], e = rep_begin_[in.cluster + 1];
  for (uint32_t i = b; i < e; ++i) {
    const LocalPoint& lp = rep_points_[i];
    const int cell = cell_of(lp.x, lp.y);
    if (!(in.footprint >> cell & 1u)) continue;
    const float z = lp.z + float(in.residual[cell]) * (1.0f / 127.0f);
    const Vec3 p = centre + in.scale * (lp.x * f.u + lp.y * f.v + z * f.n);
    const Vec3 n = (lp.nx * f.u + lp.ny * f.v + lp.nz * f.n).normalized();
    out.push_back(PackedSplat{p, 0.0f, n, in.prim});
  }
  counters.add(kCodebookPointsDecoded, e - b);
}

size_t PatchCodebook::memory_bytes() const {
  return instances_.size() * sizeof(Instance) + rep_begin_.size() * sizeof(uint32_t) +
         rep_points_.size() * sizeof(LocalPoint);
}

}  // namespace pcrt
