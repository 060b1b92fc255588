#include "core/point_cloud_io.hpp"

#include <fmt/format.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/point_stream.hpp"
#include "tests/test_helpers.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;
using pcrt::test::write_text;

namespace {

PointCloud small_cloud() {
  PointCloud c;
  c.name = "small";
  c.positions = {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(-1.5f, 0.25f, 1e-3f)};
  c.normals = {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0)};
  c.colours = {{255, 0, 0}, {0, 255, 0}, {1, 2, 3}};
  c.radii = {0.5f, 0.25f, 0.125f};
  return c;
}

// Catch2's REQUIRE_THROWS_WITH with a substring matcher.
#define REQUIRE_INPUT_ERROR(expr, text) REQUIRE_THROWS_WITH(expr, Catch::Matchers::Contains(text))

}  // namespace

TEST_CASE("PLY round trips in every format", "[io]") {
  const PointCloud c = small_cloud();
  for (PlyFormat f :
       {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian, PlyFormat::kBinaryBigEndian}) {
    const std::string path =
        (pcrt::test::scratch_dir() / ("rt" + std::to_string(int(f)) + ".ply")).string();
    write_ply(path, c, f);
    const PointCloud r = read_point_cloud(path);
    REQUIRE(r.size() == 3);
    for (size_t i = 0; i < 3; ++i) {
      REQUIRE(r.positions[i] == c.positions[i]);
      REQUIRE((r.normals[i] - c.normals[i]).norm() < 1e-6f);
      REQUIRE(r.radii[i] == c.radii[i]);
      REQUIRE(r.colours[i].b == c.colours[i].b);
    }
  }
}

TEST_CASE("PLY reads double coordinates, skips unknown properties and face lists", "[io]") {
  // Big-endian doubles with an extra int property, then a face element with lists.
  std::string bin =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
      "property double z\nproperty int label\nelement face 1\nproperty list uchar int "
      "vertex_indices\n"
      "end_header\n";
  auto put_be = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    for (size_t i = sizeof(v); i-- > 0;) bin.push_back(b[i]);
  };
  put_be(1.0), put_be(2.0), put_be(3.0), put_be(int32_t(7));
  put_be(4.0), put_be(5.0), put_be(6.0), put_be(int32_t(8));
  bin.push_back(char(3));
  put_be(int32_t(0)), put_be(int32_t(1)), put_be(int32_t(0));
  const PointCloud r = read_point_cloud(write_text("be.ply", bin));
  REQUIRE(r.size() == 2);
  REQUIRE(r.positions[1] == Vec3(4, 5, 6));
  REQUIRE(r.attributes() == std::vector<std::string>{"position"});
}

TEST_CASE("malformed PLY files are rejected with the file and place named", "[io][errors]") {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\nend_header\n";
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("trunc.ply", head + "0 0 0\n1 1 1\n")),
                      "truncated");
  REQUIRE_INPUT_ERROR(
      read_point_cloud(write_text("extra.ply", head + "0 0 0\n1 1 1\n2 2 2\n3 3 3\n")),
      "counts do not match");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("short.ply", head + "0 0 0\n1 1\n2 2 2\n")),
                      "line 9");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("nan.ply", head + "0 0 0\nnan 1 1\n2 2 2\n")),
                      "vertex 1");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("inf.ply", head + "0 0 0\n1 inf 1\n2 2 2\n")),
                      "vertex 1");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("word.ply", head + "0 0 0\n1 x 1\n2 2 2\n")),
                      "not a number");
  REQUIRE_INPUT_ERROR(
      read_point_cloud(write_text("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n")),
      "end_header");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("notply.ply", "plx\n")), "not a PLY");
  REQUIRE_INPUT_ERROR(
      read_point_cloud(write_text("empty.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 0\nproperty float "
                                  "x\nproperty float y\nproperty float z\nend_header\n")),
      "no points");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text(
                          "partn.ply",
                          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty "
                          "float y\nproperty float z\nproperty float nx\nend_header\n0 0 0 1\n")),
                      "nx, ny, nz");
  // A binary file whose header promises far more vertices than it holds fails before allocating.
  REQUIRE_INPUT_ERROR(
      read_point_cloud(
          write_text("lie.ply",
                     "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty "
                     "float x\nproperty float y\nproperty float z\nend_header\n123456789012")),
      "too short");
  const std::string bhead =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float "
      "y\nproperty float z\nend_header\n";
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("btrunc.ply", bhead + std::string(20, '\0'))),
                      "too short");
}

TEST_CASE("XYZ and PWN files: 3 or 6 columns", "[io]") {
  const PointCloud a = read_point_cloud(write_text("a.xyz", "# comment\n0 0 0\n1 0 0\n\n0 1 0\n"));
  REQUIRE(a.size() == 3);
  REQUIRE_FALSE(a.has_normals());
  const PointCloud b = read_point_cloud(write_text("b.pwn", "0 0 0 0 0 2\n1 0 0 0 0 1\n"));
  REQUIRE(b.has_normals());
  REQUIRE(b.normals[0] == Vec3(0, 0, 1));  // normalised on load
  // All-zero normals (as some CGAL files store) mean "no normals".
  REQUIRE_FALSE(read_point_cloud(write_text("z.xyz", "0 0 0 0 0 0\n1 0 0 0 0 0\n")).has_normals());
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("c.xyz", "0 0 0\n1 0\n")), "line 2");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("d.xyz", "0 0 0 1\n")), "4 columns");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("e.xyz", "0 0 nan\n")), "non-finite");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("f.xyz", "\n# nothing\n")), "no points");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("g.xyz", "0 0 0 0 0 1\n1 1 1 0 0 0\n")),
                      "zero normal");
}

TEST_CASE("OFF files: vertices become points, faces are checked", "[io]") {
  const PointCloud a =
      read_point_cloud(write_text("a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  REQUIRE(a.size() == 3);
  REQUIRE(read_point_cloud(write_text("b.off", "OFF 2 0 0\n0 0 0\n1 0 0\n")).size() == 2);
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("c.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n")),
                      "vertex 2 of 3");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("d.off", "OFF\n2 1 0\n0 0 0\n1 0 0\n3 0 1 5\n")),
                      "names vertex 5");
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("e.off", "OFX\n")), "not an OFF");
}

TEST_CASE("unknown extensions, missing files and duplicates", "[io]") {
  REQUIRE_INPUT_ERROR(read_point_cloud(write_text("a.txt", "0 0 0\n")),
                      "unknown point cloud format");
  REQUIRE_INPUT_ERROR(load_dataset("/nonexistent/cloud.ply"), "no such file");
  const PointCloud d =
      read_point_cloud(write_text("dup.xyz", "0 0 0\n1 1 1\n0 0 0\n1 1 1\n2 2 2\n"));
  REQUIRE(d.size() == 3);
  REQUIRE(d.positions[2] == Vec3(2, 2, 2));  // order of first occurrences kept
}

TEST_CASE("real scans load when fetched", "[io][data]") {
  const std::filesystem::path dir = pcrt::test::data_dir();
  if (!std::filesystem::exists(dir / "cgal"))
    PCRT_SKIP("data/ not fetched (scripts/fetch_data.sh): no real scans");
  size_t loaded = 0;
  for (const char* f :
       {"cgal/points_3/kitten.xyz", "cgal/points_3/hippo1.ply", "cgal/points_3/oni.pwn",
        "cgal/points_3/b9_training.ply", "cgal/points_3/ball.ply", "bunny/bunny.ply"}) {
    if (!std::filesystem::exists(dir / f)) continue;
    const PointCloud c = read_point_cloud((dir / f).string());
    REQUIRE(c.size() > 1000);
    ++loaded;
  }
  REQUIRE(loaded >= 5);
}

// Issue 14: what a fuzz campaign found in the readers.
TEST_CASE("hostile inputs: huge coordinates, property-less elements, endless streams",
          "[io][errors]") {
  SECTION("coordinates beyond kMaxCoordinate name the file and the element or line") {
    const std::string ply =
        write_text("far.ply",
                   "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0 0 0\n2e18 0 0\n");
    REQUIRE_INPUT_ERROR(read_point_cloud(ply), "far.ply: vertex 1 has a coordinate beyond");
    REQUIRE_INPUT_ERROR(read_point_cloud(write_text("far.xyz", "0 0 0\n0 1e30 0\n")),
                        "far.xyz: line 2: a coordinate beyond");
    REQUIRE_INPUT_ERROR(
        read_point_cloud(write_text("far.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 0 -3e38\n")),
        "far.off: line 5: vertex 2 has a coordinate beyond");
    // A generator's sizes are bounded where its points would be: the spec is named.
    REQUIRE_INPUT_ERROR(load_dataset("sphere:n=10,radius=1e20"),
                        "'sphere:n=10,radius=1e20': radius=1e+20 is outside its range");
    REQUIRE_INPUT_ERROR(load_dataset("sphere:n=10,radius=1e-25"),
                        "'sphere:n=10,radius=1e-25': radius=1e-25 is outside its range");
    // The largest accepted magnitude still loads.
    REQUIRE(read_point_cloud(write_text("edge.xyz", "0 0 0\n1e12 -1e12 1e12\n")).size() == 2);
  }
  SECTION("a binary element without properties and a huge count is refused, not looped over") {
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
        "property float y\nproperty float z\nelement foo 18446744073709551615\nend_header\n";
    ply.append(12, '\0');
    REQUIRE_INPUT_ERROR(read_point_cloud(write_text("empty_element.ply", ply)),
                        "empty_element.ply: element 'foo' has 18446744073709551615 records but "
                        "no properties");
  }
  SECTION("a stream without a size is read up to a bound") {
    REQUIRE_INPUT_ERROR(read_file("/dev/zero", 1 << 20),
                        "/dev/zero: more than 1048576 bytes from a stream without a size");
    REQUIRE_INPUT_ERROR(read_file(pcrt::test::scratch_dir().string()), "is a directory");
  }
}

// A log another process appends to (a sweep's runs.jsonl under `pcrt cluster status`) is read as
// it was when reading began; an input that grows is refused. A writer appends lines while the
// file is read: a snapshot never fails and is always a whole prefix of what is there afterwards.
TEST_CASE("read_file takes a snapshot of a file that grows while it is read", "[io]") {
  const auto path = std::filesystem::temp_directory_path() / "pcrt_growing_log.txt";
  const std::string line(255, 'x');
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    for (int i = 0; i < (1 << 16); ++i) out << line << '\n';  // 16 MiB before reading begins
  }
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    std::ofstream out(path, std::ios::binary | std::ios::app);
    while (!stop) out << line << '\n' << std::flush;
  });
  size_t smallest = SIZE_MAX;
  std::string snapshot;
  for (int attempt = 0; attempt < 5; ++attempt) {
    snapshot = read_file(path.string(), kMaxStreamBytes, FileGrowth::kSnapshot);
    smallest = std::min(smallest, snapshot.size());
  }
  stop = true;
  writer.join();
  std::ifstream in(path, std::ios::binary);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  CHECK(smallest >= (size_t(1) << 24));
  REQUIRE(snapshot.size() <= after.size());
  CHECK(after.compare(0, snapshot.size(), snapshot) == 0);
}

namespace {

// A 3D Gaussian Splatting trainer's layout, as it writes it: zero normals, SH degree 1 (f_rest).
std::string gaussian_ply(const std::string& vertices, int count) {
  std::string h = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(count) +
                  "\nproperty float x\nproperty float y\nproperty float z\n"
                  "property float nx\nproperty float ny\nproperty float nz\n";
  for (const char* p : {"f_dc_0", "f_dc_1", "f_dc_2", "f_rest_0", "f_rest_1", "f_rest_2", "opacity",
                        "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"})
    h += std::string("property float ") + p + "\n";
  return h + "end_header\n" + vertices;
}

}  // namespace

TEST_CASE("3D Gaussian Splatting files load activated, with their shortest axis as normal",
          "[io][gaussians]") {
  // Particle 0: scales e^0, e^-3, e^-1 (shortest: y), a 90 degree turn about z (w = x... = 1, 0,
  // 0, 1 unnormalised), opacity logit 0 (1/2), f_dc 0 (grey). Particle 1: the identity rotation.
  const PointCloud c = read_point_cloud(
      write_text("gs.ply", gaussian_ply("0 0 0 0 0 0 0 0 0 0.1 0.2 0.3 0 0 -3 -1 1 0 0 1\n"
                                        "1 2 3 0 0 0 1 -1 0 0 0 0 2 -2 -2 -5 2 0 0 0\n",
                                        2)));
  REQUIRE(c.has_gaussians());
  REQUIRE(c.attributes() == std::vector<std::string>{"position", "normal", "colour", "gaussian"});
  const GaussianParticles& g = c.gaussians;
  // Found by position, whatever order the reader keeps.
  const size_t a = c.positions[0].isZero() ? 0 : 1, b = 1 - a;
  REQUIRE((g.scales[a] - Vec3(1, std::exp(-3.0f), std::exp(-1.0f))).norm() < 1e-6f);
  REQUIRE(g.opacities[a] == Approx(0.5f));
  REQUIRE(g.opacities[b] == Approx(1 / (1 + std::exp(-2.0f))));
  REQUIRE((g.rotations[a] - Vec4(1, 0, 0, 1) / std::sqrt(2.0f)).norm() < 1e-6f);
  // Axis y turned 90 degrees about z is -x; the normal's sign is the quaternion's.
  REQUIRE(std::abs(c.normals[a].x()) == Approx(1.0f));
  REQUIRE(std::abs(c.normals[b].z()) == Approx(1.0f));
  REQUIRE(c.colours[a].r == 128);
  REQUIRE(c.colours[b].r == std::lround((0.5 + kShC0) * 255));
  REQUIRE(c.colours[b].g == std::lround((0.5 - kShC0) * 255));
}

TEST_CASE("Gaussian particles round trip through the standard layout", "[io][gaussians]") {
  PointCloud c = small_cloud();
  c.radii.clear();
  c.gaussians.scales = {Vec3(0.1f, 0.2f, 0.001f), Vec3(1, 1, 1), Vec3(3, 2, 1)};
  c.gaussians.rotations = {Vec4(1, 0, 0, 0), Vec4(0.5f, 0.5f, 0.5f, 0.5f), Vec4(0, 0, 1, 0)};
  c.gaussians.opacities = {0.5f, 1.0f, 0.01f};
  for (PlyFormat f : {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
    const std::string path =
        (pcrt::test::scratch_dir() / ("grt" + std::to_string(int(f)) + ".ply")).string();
    write_ply(path, c, f);
    const PointCloud r = read_ply(path);
    REQUIRE(r.size() == 3);
    for (size_t i = 0; i < 3; ++i) {
      REQUIRE(r.positions[i] == c.positions[i]);
      REQUIRE((r.gaussians.scales[i] - c.gaussians.scales[i]).norm() <
              1e-5f * c.gaussians.scales[i].norm());
      REQUIRE((r.gaussians.rotations[i] - c.gaussians.rotations[i]).norm() < 1e-6f);
      REQUIRE(r.gaussians.opacities[i] == Approx(c.gaussians.opacities[i]).margin(2e-6));
      REQUIRE(r.colours[i].g == c.colours[i].g);
      // A Gaussian file's normals are its particles' shortest axes, whatever it stores.
      const Vec3 axis = shortest_axis(c.gaussians.scales[i], c.gaussians.rotations[i]);
      REQUIRE((r.normals[i] - axis).norm() < 1e-6f);
    }
  }
}

TEST_CASE("malformed Gaussian files are rejected with the file and vertex named",
          "[io][gaussians][errors]") {
  auto one = [](const std::string& name, const std::string& row) {
    return read_point_cloud(write_text(name, gaussian_ply(row + "\n", 1)));
  };
  REQUIRE_INPUT_ERROR(one("gzero.ply", "0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0"),
                      "vertex 0 has a zero or non-finite rotation");
  REQUIRE_INPUT_ERROR(one("gbig.ply", "0 0 0 0 0 0 0 0 0 0 0 0 0 1000 0 0 1 0 0 0"),
                      "beyond float's range");
  REQUIRE_INPUT_ERROR(one("gnan.ply", "0 0 0 0 0 0 0 0 0 0 0 0 nan 0 0 0 1 0 0 0"),
                      "non-finite opacity");
  REQUIRE_INPUT_ERROR(
      read_point_cloud(write_text(
          "gpart.ply",
          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
          "property float z\nproperty float opacity\nproperty float scale_0\nend_header\n"
          "0 0 0 0 0\n")),
      "only some of the Gaussian properties");
  REQUIRE_INPUT_ERROR(
      read_point_cloud(write_text("gdc.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                  "property float y\nproperty float z\nproperty float f_dc_0\n"
                                  "end_header\n0 0 0 0\n")),
      "only some of f_dc_0..2");
  PointCloud bad = small_cloud();
  bad.gaussians.scales = {Vec3(1, 1, 1), Vec3(1, 0, 1), Vec3(1, 1, 1)};
  bad.gaussians.rotations.assign(3, Vec4(1, 0, 0, 0));
  bad.gaussians.opacities.assign(3, 0.5f);
  REQUIRE_INPUT_ERROR(bad.validate(), "point 1 has Gaussian scales");
  bad.gaussians.scales[1] = Vec3(1, 1, 1);
  bad.gaussians.opacities[2] = 1.5f;
  REQUIRE_INPUT_ERROR(bad.validate(), "point 2 has opacity");
  bad.gaussians.opacities.pop_back();
  REQUIRE_INPUT_ERROR(bad.validate(), "2 opacities for 3 points");
}

namespace {

// Every point a stream delivers, in order.
PointCloud drain(const PointStream& stream) {
  PointCloud c;
  stream.read([&](const PointChunk& k) {
    c.positions.insert(c.positions.end(), k.positions.begin(), k.positions.end());
    c.normals.insert(c.normals.end(), k.normals.begin(), k.normals.end());
  });
  return c;
}

// The file at `path` streams the points, normals, origin and bounds of `read`, its whole read.
void check_streams_as_read(const std::string& path, const PointCloud& read) {
  const auto stream = open_point_stream(path);
  REQUIRE(stream->size() == read.size());
  CHECK(stream->origin() == read.origin);
  const PointCloud streamed = drain(*stream);
  CHECK(streamed.positions == read.positions);
  CHECK(streamed.normals == read.normals);
  CHECK(stream->bounds().lo == read.bounds().lo);
  CHECK(stream->bounds().hi == read.bounds().hi);
}

}  // namespace

// `pcrt render --stream` on a file: the reader's points, origin and normals, chunk by chunk.
TEST_CASE("a PLY file streams the points read_ply reads", "[io][stream]") {
  PointCloud cloud = load_dataset_in_input_order("torus:n=150000,seed=3").cloud;
  for (const bool georeferenced : {false, true}) {
    cloud.origin = georeferenced ? Vec3d(597000.25, -244000.5, 12.0) : Vec3d::Zero();
    for (PlyFormat f :
         {PlyFormat::kBinaryLittleEndian, PlyFormat::kBinaryBigEndian, PlyFormat::kAscii}) {
      INFO("georeferenced " << georeferenced << ", format " << int(f));
      const std::string path = (pcrt::test::scratch_dir() / "stream.PLY").string();
      write_ply(path, cloud, f);
      check_streams_as_read(path, read_ply(path));
    }
  }
}

namespace {

// The cloud as XYZ text, x y z nx ny nz, each number written to round-trip (positions in the
// file's own coordinates: origin + local, in double), with a comment and a blank line.
std::string xyz_text(const PointCloud& c) {
  std::string t = "# x y z nx ny nz\n";
  for (size_t i = 0; i < c.size(); ++i) {
    const Vec3d w = c.origin + c.positions[i].cast<double>();
    const Vec3& n = c.normals[i];
    t += fmt::format("{} {} {} {} {} {}\n", w.x(), w.y(), w.z(), n.x(), n.y(), n.z());
    if (i == 7) t += "\n";
  }
  return t;
}

}  // namespace

// Over several of the stream's 4 MiB blocks and 2^16-point chunks.
TEST_CASE("an XYZ or PWN file streams the points read_xyz reads", "[io][stream]") {
  PointCloud cloud = load_dataset_in_input_order("torus:n=150000,seed=3").cloud;
  for (const bool georeferenced : {false, true}) {
    cloud.origin = georeferenced ? Vec3d(597000.25, -244000.5, 12.0) : Vec3d::Zero();
    for (const char* name : {"stream.xyz", "stream.PWN"}) {
      INFO("georeferenced " << georeferenced << ", " << name);
      const std::string path = write_text(name, xyz_text(cloud));
      check_streams_as_read(path, read_xyz(path));
    }
  }
}

// CGAL's building scan, an ascii PLY of 10^5 points with normals, over several 4 MiB blocks.
TEST_CASE("a real ascii PLY streams the points read_ply reads", "[io][stream]") {
  const std::string path = (pcrt::test::data_dir() / "cgal" / "points_3" / "building.ply").string();
  if (!std::filesystem::exists(path)) PCRT_SKIP("data/ not fetched (scripts/fetch_data.sh)");
  const PointCloud read = read_ply(path);
  REQUIRE(read.size() == 100000);
  check_streams_as_read(path, read);
}

TEST_CASE("an XYZ stream names the file and line of what is wrong", "[io][stream][errors]") {
  const auto open = [](const char* name, const std::string& text) {
    return open_point_stream(write_text(name, text));
  };
  REQUIRE_INPUT_ERROR(open("none.xyz", ""), "none.xyz: no points");
  REQUIRE_INPUT_ERROR(open("four.xyz", "1 2 3 4\n"), "four.xyz: line 1: 4 columns");
  REQUIRE_INPUT_ERROR(open("five.xyz", "0 0 0 0 0 1\n# c\n1 1 1 0 1\n"),
                      "five.xyz: line 3: 5 columns where earlier lines have 6");
  REQUIRE_INPUT_ERROR(open("zero.xyz", "0 0 0 0 0 0\n1 1 1 0 0 0\n"),
                      "zero.xyz: every normal is zero");
  REQUIRE_INPUT_ERROR(open("word.xyz", "0 0 0 0 0 1\n1 1 1 0 x 1\n"),
                      "word.xyz: line 2: 'x' is not a number");
  // What only a full read finds: bounds() reads every point.
  REQUIRE_INPUT_ERROR(open("zn.xyz", "0 0 0 0 0 1\n1 1 1 0 0 0\n")->bounds(),
                      "zn.xyz: line 2: a zero or non-finite normal");
  REQUIRE_INPUT_ERROR(open("inf.xyz", "0 0 0 0 0 1\n1 inf 1 0 0 1\n")->bounds(),
                      "inf.xyz: line 2: a coordinate");
  // Line numbers past the first 4 MiB block.
  std::string big;
  for (int i = 0; i < 200000; ++i) big += fmt::format("{} 0.5 0.25 0 0 1\n", i);
  REQUIRE_INPUT_ERROR(open("late.xyz", big + "1 2 3 0 0 y\n"),
                      "late.xyz: line 200001: 'y' is not a number");
  // A file that changed between the count and a read.
  const std::string grown = write_text("grown.xyz", "0 0 0 0 0 1\n");
  const auto stream = open_point_stream(grown);
  write_text("grown.xyz", "0 0 0 0 0 1\n1 1 1 0 0 1\n");
  REQUIRE_INPUT_ERROR(stream->bounds(), "grown.xyz: line 2: more points than when it was opened");
}

TEST_CASE("a file that cannot stream is one error naming it", "[io][stream][errors]") {
  const PointCloud cloud = load_dataset_in_input_order("sphere:n=1000").cloud;
  const auto dir = pcrt::test::scratch_dir();
  const std::string ascii = (dir / "ascii.ply").string(), bare = (dir / "bare.ply").string(),
                    cut = (dir / "cut.ply").string(), xyz = (dir / "c.xyz").string();
  write_ply(ascii, cloud, PlyFormat::kAscii);
  const std::string text = read_file(ascii);
  write_text("short.ply", text.substr(0, text.rfind('\n', text.size() / 2) + 1));  // 500 lines
  const size_t line3 = text.find("end_header\n") + 11;
  const size_t after = text.find('\n', text.find('\n', line3) + 1) + 1;  // two vertex lines
  write_text("few.ply", text.substr(0, after) + "1 2 3 0 0\n" + text.substr(after));
  write_text("word.ply", text.substr(0, after) + "1 2 3 0 0 y\n" + text.substr(after));
  PointCloud no_normals = cloud;
  no_normals.normals.clear();
  write_ply(bare, no_normals);
  write_ply(cut, cloud);
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) - 7);
  write_text(xyz, "0 0 0\n1 0 0\n");
  CHECK(drain(*open_point_stream(ascii)).positions == read_ply(ascii).positions);
  REQUIRE_INPUT_ERROR(open_point_stream((dir / "short.ply").string())->bounds(),
                      "short.ply: truncated: file ends at 'vertex' element");
  REQUIRE_INPUT_ERROR(open_point_stream((dir / "few.ply").string())->bounds(),
                      "few.ply: line 14: 'vertex' element 2 has too few values");
  REQUIRE_INPUT_ERROR(open_point_stream((dir / "word.ply").string())->bounds(),
                      "word.ply: line 14: 'y' is not a number");
  REQUIRE_INPUT_ERROR(open_point_stream(bare), "bare.ply: has no normals");
  REQUIRE_INPUT_ERROR(open_point_stream(cut), "cut.ply: truncated");
  REQUIRE_INPUT_ERROR(open_point_stream(xyz), "c.xyz: has no normals");
  REQUIRE_INPUT_ERROR(open_point_stream(dir.string() + "/"), "only PLY, XYZ and PWN files");
}
