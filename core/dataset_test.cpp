#include "core/dataset.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.hpp"
#include "core/point_cloud.hpp"
#include "core/point_stream.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

TEST_CASE("generated clouds lie on their exact surface with exact normals", "[data]") {
  for (const char* spec :
       {"sphere:n=2000", "fibonacci_sphere:n=2000", "plane:n=2000", "torus:n=2000",
        "bumpy_sphere:n=2000", "sphere:n=2000,density=0.8", "torus:n=500,R=2,r=0.5"}) {
    INFO(spec);
    const Dataset d = load_dataset(spec);
    REQUIRE(d.cloud.size() ==
            (std::string(spec).find("n=500") != std::string::npos ? 500u : 2000u));
    REQUIRE(d.cloud.has_normals());
    for (size_t i = 0; i < d.cloud.size(); ++i) {
      REQUIRE(std::abs(d.truth->signed_distance(d.cloud.positions[i])) < 2e-5f);
      REQUIRE(d.truth->normal(d.cloud.positions[i]).dot(d.cloud.normals[i]) > 0.9999f);
    }
  }
}

TEST_CASE("default shapes are the documented ones", "[data]") {
  const Dataset s = load_dataset("sphere:n=1000");
  REQUIRE(std::abs(s.cloud.positions[17].norm() - 1.0f) < 1e-6f);
  const Dataset t = load_dataset("torus:n=1000");
  for (const Vec3& p : t.cloud.positions) {
    const float q = std::hypot(p.x(), p.y()) - 1.0f;
    REQUIRE(std::abs(std::hypot(q, p.z()) - 0.25f) < 1e-5f);
  }
}

TEST_CASE("generators are seeded and reproducible", "[data]") {
  const auto a = load_dataset("torus:n=300,seed=7,noise=0.01").cloud.positions;
  const auto b = load_dataset("torus:n=300,seed=7,noise=0.01").cloud.positions;
  const auto c = load_dataset("torus:n=300,seed=8,noise=0.01").cloud.positions;
  REQUIRE(a == b);
  REQUIRE(a != c);
}

TEST_CASE("noise has the requested standard deviation", "[data]") {
  const Dataset d = load_dataset("plane:n=20000,noise=0.01,size=10");
  double sum2 = 0;
  for (const Vec3& p : d.cloud.positions) sum2 += double(p.z()) * p.z();
  REQUIRE(std::sqrt(sum2 / 20000) == Approx(0.01).epsilon(0.03));
}

TEST_CASE("non-uniform density thins along x", "[data]") {
  const Dataset d = load_dataset("plane:n=20000,density=0.9");
  size_t left = 0;
  for (const Vec3& p : d.cloud.positions) left += p.x() < 0;
  // Density 1 -> 0.1 linearly: the left half holds (1 + 0.55)/(2 * 0.55) ... = 0.7045 of the
  // points.
  REQUIRE(double(left) / 20000 == Approx(0.7045).epsilon(0.03));
}

TEST_CASE("exact ray intersection: analytic and sphere-traced agree", "[data]") {
  SphereSurface s;
  Ray r{Vec3(0.3f, -5, 0.2f), Vec3(0, 1, 0)};
  float t = 0;
  Vec3 n;
  REQUIRE(s.intersect(r, t, n));
  REQUIRE(t == Approx(5 - std::sqrt(1 - 0.09 - 0.04)).epsilon(1e-6));
  // The generic path (used for the torus and the bumpy sphere) on the same sphere.
  float t2 = 0;
  REQUIRE(s.Surface::intersect(r, t2, n));
  REQUIRE(t2 == Approx(t).margin(1e-5));
  TorusSurface torus;
  REQUIRE(torus.intersect(Ray{Vec3(-5, 0, 0), Vec3(1, 0, 0)}, t, n));
  REQUIRE(t == Approx(3.75).margin(1e-5));
  REQUIRE(n.x() == Approx(-1).margin(1e-4));
  REQUIRE_FALSE(torus.intersect(Ray{Vec3(0, 0, 5), Vec3(0, 0, -1)}, t, n));  // through the hole
}

TEST_CASE("bad dataset specs are one-line errors naming the spec", "[data][errors]") {
  using Catch::Matchers::Contains;
  REQUIRE_THROWS_WITH(load_dataset("sphere:n=0"), Contains("n=0"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:n=1.5"), Contains("integer"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:foo=1"), Contains("unknown parameter 'foo'"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:noise=nan"), Contains("not finite"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:n=abc"), Contains("not a number"));
  REQUIRE_THROWS_WITH(load_dataset("cylinder:n=5"), Contains("not a generator"));
  REQUIRE_THROWS_WITH(load_dataset("torus:R=1,r=2"), Contains("smaller than R"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:n"), Contains("key=value"));
  REQUIRE_THROWS_WITH(load_dataset("sphere:n=5,n=6"), Contains("twice"));
}

TEST_CASE("a generator's stream delivers its cloud's points in input order", "[data]") {
  for (const char* spec :
       {"torus:n=150000,seed=7,noise=0.01,density=0.5", "fibonacci_sphere:n=70000,radius=2"}) {
    INFO(spec);
    const PointCloud cloud = load_dataset_in_input_order(spec).cloud;
    const auto stream = open_point_stream(spec);
    REQUIRE(stream->size() == cloud.size());
    for (int pass = 0; pass < 2; ++pass) {  // every read the same points
      size_t next = 0;
      bool same = true;
      stream->read([&](const PointChunk& c) {
        CHECK(c.first == next);
        CHECK(c.positions.size() <= PointStream::kChunkPoints);
        REQUIRE(c.normals.size() == c.positions.size());
        for (size_t i = 0; i < c.positions.size(); ++i)
          same &= c.positions[i] == cloud.positions[next + i] &&
                  c.normals[i] == cloud.normals[next + i];
        next += c.positions.size();
      });
      CHECK(next == cloud.size());
      CHECK(same);
    }
    CHECK(stream->bounds().lo == cloud.bounds().lo);
    CHECK(stream->bounds().hi == cloud.bounds().hi);
  }
}

TEST_CASE("only surface generators stream: one-line errors naming the input", "[data][errors]") {
  using Catch::Matchers::Contains;
  REQUIRE_THROWS_WITH(open_point_stream("ball:n=100"),
                      Contains("ball:n=100") && Contains("normals"));
  REQUIRE_THROWS_WITH(open_point_stream("cylinder:n=5"), Contains("not a generator"));
  REQUIRE_THROWS_WITH(open_point_stream((test::source_dir() / "README.md").string()),
                      Contains("only PLY, XYZ and PWN files"));
  REQUIRE_THROWS_WITH(open_point_stream(""), Contains("empty name"));
}

TEST_CASE("volume generators: ball, cube and skew lines", "[dataset]") {
  const Dataset ball = load_dataset("ball:n=2000,size=2");
  REQUIRE(ball.cloud.size() == 2000);
  REQUIRE(ball.truth == nullptr);
  for (const Vec3& p : ball.cloud.positions) REQUIRE(p.norm() <= 1.0f);
  const Dataset cube = load_dataset("cube:n=500,size=4");
  for (const Vec3& p : cube.cloud.positions) REQUIRE(p.cwiseAbs().maxCoeff() <= 2.0f);
  const Dataset lines = load_dataset("skew_lines:n=101");
  size_t on_x = 0;
  for (const Vec3& p : lines.cloud.positions) {
    const bool a = p.y() == 0 && p.z() == -1, b = p.x() == 0 && p.z() == 1;
    REQUIRE((a || b));
    on_x += a;
  }
  REQUIRE(on_x == 51);
}
