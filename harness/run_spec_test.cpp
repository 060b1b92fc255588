// Runs as typed values: the JSON they are written as is the JSON committed results hold (keys,
// number types), so run keys, --resume, merges and the op gate's baseline stay valid.
#include "harness/run_spec.hpp"

#include <catch2/catch.hpp>
#include <fstream>
#include <limits>

#include "core/error.hpp"
#include "harness/csv_table.hpp"
#include "harness/run_files.hpp"
#include "harness/sweep_fits.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

namespace {

// A line of results/thesis/runs.jsonl, as the sweep wrote it.
const char* kBuildResult =
    R"({"M":4096,"N":2500,"counters":{},"dataset":"sphere","experiment":"build_sphere","extra":{"prepare_s":0.001309782,"structure_bytes":74888},"kind":"build","measure":"both","method":"reference_splat","prepare_counters":{"build_item_refs":17390,"build_item_visits":19890,"build_nodes":1331,"knn_queries":2500,"knn_results":22500},"reps":5,"seed":1,"set":{},"spec":{"N":2500.0,"dataset":"sphere","experiment":"build_sphere","kind":"build","measure":"both","method":"reference_splat","reps":5,"seed":1,"set":{},"structure":"grid","threads":2,"warmup":0},"status":"ok","structure":"grid","threads":2,"time_max_s":0.000319784,"time_median_s":0.000225074,"time_min_s":0.000194549,"time_spread":0.5564170006309036,"times_s":[0.000319784,0.000225074,0.000196361,0.000233516,0.000194549],"wall_s":0.014904894,"warmup":0})";

}  // namespace

TEST_CASE("a result read and written again is the same JSON", "[sweep][runs]") {
  const json line = json::parse(kBuildResult);
  const RunResult r = line.get<RunResult>();
  REQUIRE(r.spec.kind == RunKind::kBuild);
  REQUIRE(r.ok());
  REQUIRE(*r.points == 2500);
  REQUIRE(*r.spec.N == 2500.0);
  REQUIRE(r.prepare_counters->at("knn_results") == 22500);
  REQUIRE(json(r).dump() == line.dump());
  REQUIRE(run_key(r) == json::parse(kBuildResult)["spec"].dump());
}

TEST_CASE("every committed thesis result reads and writes back byte for byte", "[sweep][runs]") {
  // Every kind's measurements (build, render, reconstruct, crossover) as the sweep wrote them.
  std::ifstream in(test::source_dir() / "results/thesis/runs.jsonl");
  REQUIRE(in);
  std::map<RunKind, int> kinds;
  for (std::string line; std::getline(in, line);) {
    const RunResult r = json::parse(line).get<RunResult>();
    ++kinds[r.spec.kind];
    REQUIRE(json(r).dump() == json::parse(line).dump());
  }
  for (RunKind k : {RunKind::kRender, RunKind::kBuild, RunKind::kReconstruct, RunKind::kCrossover})
    REQUIRE(kinds[k] > 0);
}

TEST_CASE("a crossover whose mesh never pays off writes null frames and reads them back",
          "[sweep][runs]") {
  RunMeasures m;
  m.crossover = CrossoverMeasures{1, 2, 3, 4, 0.5, 10, std::nullopt};
  const json j = m;
  REQUIRE(j["crossover_frames"].is_null());
  REQUIRE(j["triangles"].is_number_unsigned());
  REQUIRE(!j.contains("prepare_s"));
  REQUIRE(j.get<RunMeasures>() == m);
  m.crossover->crossover_frames = 7.5;
  REQUIRE(json(m).get<RunMeasures>() == m);
  REQUIRE(json(RunMeasures{}) == json::object());
}

TEST_CASE("specs write only the keys their kind uses", "[sweep][runs]") {
  RunSpec w;
  w.kind = RunKind::kWorkload;
  w.workload = "sort";
  w.N = 1000;
  const json j = w;
  REQUIRE(!j.contains("dataset"));
  REQUIRE(!j.contains("method"));
  REQUIRE(!j.contains("set"));
  REQUIRE(j["N"].is_number_float());
  REQUIRE(j.get<RunSpec>().workload == "sort");
  RunSpec c;
  c.kind = RunKind::kCrossover;
  c.dataset = "sphere";
  c.dataset_path = "/data/sphere";
  c.method = "hubo_2006";
  c.reconstruction = "afsr";
  c.engine = "bvh";
  const json cj = c;
  REQUIRE(cj["set"] == json::object());
  REQUIRE(cj["engine"] == "bvh");
  // Where the data lies is not what the run is.
  REQUIRE(json::parse(run_key(c)).count("dataset_path") == 0);
  REQUIRE_THROWS_AS(json({{"kind", "paint"}}).get<RunSpec>(), InputError);
}

TEST_CASE("a failed run keeps its spec and error, and no measurements", "[sweep][runs]") {
  RunSpec s;
  s.kind = RunKind::kRender;
  s.dataset = "sphere";
  s.method = "hubo_2006";
  s.N = 100;
  RunResult r = failed_run(s, RunStatus::kTimeout, "exceeded the time limit of 1 s");
  r.wall_s = 1.5;
  const json j = r;
  REQUIRE(j["status"] == "timeout");
  REQUIRE(!j.contains("counters"));
  REQUIRE(!j.contains("times_s"));
  REQUIRE(j.get<RunResult>().error == "exceeded the time limit of 1 s");
  const json row = run_row(r);
  REQUIRE(row["status"] == "timeout");
  REQUIRE(row["time_median_s"].is_null());
}

TEST_CASE("fits group runs by what they are, never by what they measured", "[sweep][fit]") {
  for (const char* c : {"experiment", "method", "N", "B", "set_leaf_size"})
    REQUIRE(is_identity_column(c));
  for (const char* c : {"ops_nodes_visited", "time_median_s", "time_noisy", "K", "k", "I", "I_run",
                        "prepare_s", "structure_bytes", "status", "error"})
    REQUIRE(!is_identity_column(c));
}

TEST_CASE("CSV cells are quoted where RFC 4180 needs it", "[sweep][csv]") {
  REQUIRE(csv_cell(json("plain")) == "plain");
  REQUIRE(csv_cell(json("a, b")) == "\"a, b\"");
  REQUIRE(csv_cell(json("say \"x\"")) == "\"say \"\"x\"\"\"");
  REQUIRE(csv_cell(json("two\nlines")) == "\"two\nlines\"");
  REQUIRE(csv_cell(json(nullptr)).empty());
  REQUIRE(csv_cell(json(0.1234567890123)) == "0.123456789");
  REQUIRE(csv_cell(json(uint64_t(12345678901))) == "12345678901");
  REQUIRE(csv_cell(json(true)) == "true");
  REQUIRE(csv_cell(json(std::numeric_limits<double>::infinity())).empty());
}
