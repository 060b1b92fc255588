#include "render/render_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pcrt {

Ray Transform::to_object(const Ray& ray) const {
  const float inv = 1.0f / scale;
  Ray r;
  r.o = inv * (rotate.transpose() * (ray.o - translate));
  r.d = rotate.transpose() * ray.d;
  r.tmin = ray.tmin * inv;
  r.tmax = ray.tmax * inv;
  return r;
}

void Transform::hit_to_world(Hit& hit) const {
  hit.t *= scale;
  hit.p = translate + scale * (rotate * hit.p);
  hit.n = (rotate * hit.n).normalized();
  hit.footprint *= scale;
}

Aabb Transform::to_world(const Aabb& box) const {
  Aabb out;
  if (box.empty()) return out;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c((corner & 1) ? box.hi.x() : box.lo.x(), (corner & 2) ? box.hi.y() : box.lo.y(),
                 (corner & 4) ? box.hi.z() : box.lo.z());
    out.extend(translate + scale * (rotate * c));
  }
  return out;
}

Aabb RenderScene::bounds() const {
  Aabb b;
  for (const SceneObject& o : objects) b.extend(o.bounds);
  return b;
}

bool RenderScene::closest_hit(const Ray& ray, Hit& hit, uint32_t& object,
                              OpCounters& counters) const {
  bool found = false;
  for (uint32_t i = 0; i < objects.size(); ++i) {
    const SceneObject& o = objects[i];
    const bool moved = !o.transform.identity();
    Ray r = moved ? o.transform.to_object(ray) : ray;
    Hit h;
    if (found) r.tmax = std::min(r.tmax, moved ? hit.t / o.transform.scale : hit.t);
    h.t = r.tmax;
    if (!o.geometry->closest_hit(r, h, counters)) continue;
    if (moved) o.transform.hit_to_world(h);
    hit = h, object = i, found = true;
  }
  return found;
}

bool RenderScene::any_hit(const Ray& ray, OpCounters& counters) const {
  for (const SceneObject& o : objects) {
    const bool moved = !o.transform.identity();
    if (o.geometry->any_hit(moved ? o.transform.to_object(ray) : ray, counters)) return true;
  }
  return false;
}

void RenderScene::any_hits(const Ray* rays, int n, char* blocked, OpCounters& counters) const {
  if (objects.size() != 1) {
    for (int i = 0; i < n; ++i) blocked[i] = char(any_hit(rays[i], counters));
    return;
  }
  const SceneObject& o = objects[0];
  if (o.transform.identity()) return o.geometry->any_hits(rays, n, blocked, counters);
  std::array<Ray, 16> moved;
  for (int i = 0; i < n; i += int(moved.size())) {
    const int m = std::min(int(moved.size()), n - i);
    for (int k = 0; k < m; ++k) moved[size_t(k)] = o.transform.to_object(rays[i + k]);
    o.geometry->any_hits(moved.data(), m, blocked + i, counters);
  }
}

Material RenderScene::material_at(uint32_t object, uint32_t prim) const {
  const SceneObject& o = objects[object];
  Material m = o.material;
  if (m.kind == MaterialKind::kDiffuse && o.points && o.points->has_colours() &&
      prim < o.points->size()) {
    const Rgb8 c = o.points->colours[prim];
    auto lin = [](uint8_t v) { return std::pow(float(v) / 255.0f, 2.2f); };
    m.albedo = Vec3(lin(c.r), lin(c.g), lin(c.b));
  }
  return m;
}

RenderScene single_object_scene(const SceneIntersector& scene, const PointCloud& cloud,
                                const Vec3& view, const Vec3& up, bool point_light) {
  RenderScene rs = single_object_scene(scene, cloud.bounds(), cloud.name, view, up, point_light);
  rs.objects[0].points = &cloud;
  return rs;
}

RenderScene single_object_scene(const SceneIntersector& scene, const Aabb& bounds,
                                const std::string& name, const Vec3& view, const Vec3& up_dir,
                                bool point_light) {
  RenderScene rs;
  rs.objects.push_back(SceneObject{&scene, nullptr, Material{}, Transform{}, bounds, name});
  if (point_light) {
    // Above and to the left of the camera, in the frame the camera's up vector defines; its
    // intensity gives a white surface facing it at the scene's distance irradiance pi * 0.8.
    const float diag = positive_or(bounds.diagonal(), 1e-6f);
    const Vec3 up = up_dir.normalized();
    const Vec3 side = view.normalized().cross(up).normalized();
    Light light;
    light.position = bounds.center() + diag * (0.9f * view.normalized() + 1.2f * up - 0.6f * side);
    const float dist = (light.position - bounds.center()).norm();
    light.power = Vec3::Constant(0.8f * kPi * dist * dist);
    rs.lights.push_back(light);
  }
  Light sky;
  sky.kind = LightKind::kSky;
  sky.sampled = false;
  rs.lights.push_back(sky);
  return rs;
}

}  // namespace pcrt
