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
#include "tests/test_helpers.hpp"
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

namespace {

// kBuildResult with one value replaced: `path` is a JSON pointer, `value` JSON text.
json edited_result(const char* path, const char* value) {
  json line = json::parse(kBuildResult);
  line[json::json_pointer(path)] = json::parse(value);
  return line;
}

std::string thrown_by(const json& line) {
  try {
    (void)line.get<RunResult>();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

}  // namespace

// Issue 29: nlohmann's get<uint64_t> wraps -5000 to 1.8e19 (a verdict flipped) and casts 1e308
// (undefined); a count must be a non-negative JSON integer within uint64, else an error naming it.
TEST_CASE("a counter read back is a non-negative integer within uint64, or an error naming it",
          "[sweep][runs]") {
  const std::pair<const char*, const char*> bad[] = {
      {"/prepare_counters/knn_queries", "-5000"},
      {"/prepare_counters/knn_queries", "1e308"},
      {"/prepare_counters/knn_queries", "2500.0"},
      {"/prepare_counters/knn_queries", "18446744073709551616"},  // 2^64: parsed as a float
      {"/prepare_counters/knn_queries", "\"2500\""},
      {"/prepare_counters/knn_queries", "null"},
      {"/prepare_counters", "[1, 2]"},
      {"/counters", "7"},
      {"/extra/structure_bytes", "-1"},
      {"/N", "-2500"},
  };
  for (const auto& [path, value] : bad) {
    CAPTURE(path, value);
    const std::string what = thrown_by(edited_result(path, value));
    const std::string name = std::string(path).substr(std::string(path).rfind('/') + 1);
    REQUIRE(what.find(name) != std::string::npos);
  }
  // The largest count is one.
  const json max = edited_result("/prepare_counters/knn_queries", "18446744073709551615");
  REQUIRE(max.get<RunResult>().prepare_counters->at("knn_queries") == UINT64_MAX);
  // Through the file reader: the file, its line and the counter.
  json bad_line = json::parse(kBuildResult);
  bad_line["prepare_counters"]["knn_queries"] = -5000;
  const std::string path =
      test::write_text("counters.jsonl", std::string(kBuildResult) + "\n" + bad_line.dump() + "\n");
  try {
    (void)read_runs_jsonl(path);
    FAIL("a counter of -5000 was read");
  } catch (const InputError& e) {
    const std::string what = e.what();
    REQUIRE(what.find(path + ": line 2") != std::string::npos);
    REQUIRE(what.find("knn_queries") != std::string::npos);
  }
}

TEST_CASE("a run spec read back has every field checked, naming it", "[sweep][runs]") {
  const std::pair<const char*, const char*> bad[] = {
      {"/spec/reps", "-1"},       {"/spec/reps", "1e30"},  {"/spec/reps", "2.5"},
      {"/spec/threads", "\"2\""}, {"/spec/warmup", "101"}, {"/spec/seed", "-1"},
      {"/spec/seed", "1e30"},     {"/spec/N", "1e30"},     {"/spec/N", "-3"},
      {"/spec/N", "\"2500\""},    {"/spec/B", "0.5"},      {"/spec/set", "[1]"},
      {"/spec/set/K", "\"x\""},   {"/spec/method", "5"},   {"/spec/kind", "3"},
  };
  for (const auto& [path, value] : bad) {
    CAPTURE(path, value);
    const std::string what = thrown_by(edited_result(path, value));
    const std::string name = std::string(path).substr(std::string(path).find('/', 1) + 1);
    REQUIRE(what.find(name.substr(0, name.find('/'))) != std::string::npos);
  }
  REQUIRE(thrown_by(edited_result("/status", "1")).find("status") != std::string::npos);
  json no_kind = json::parse(kBuildResult);
  no_kind["spec"].erase("kind");
  REQUIRE(thrown_by(no_kind).find("kind") != std::string::npos);
}

TEST_CASE("a runs file says whether its last line was torn", "[sweep][runs]") {
  const std::string line = kBuildResult;
  const std::string whole = test::write_text("whole.jsonl", line + "\n" + line + "\n");
  REQUIRE(!read_runs_file(whole).torn_tail);
  REQUIRE(read_runs_file(whole).runs.size() == 2);
  // No newline after valid JSON: the result is read, but the file was cut.
  const std::string no_newline = test::write_text("no_newline.jsonl", line + "\n" + line);
  REQUIRE(read_runs_file(no_newline).torn_tail);
  REQUIRE(read_runs_file(no_newline).runs.size() == 2);
  const std::string cut = test::write_text("cut.jsonl", line + "\n" + line.substr(0, 40) + "\n");
  REQUIRE(read_runs_file(cut).torn_tail);
  REQUIRE(read_runs_file(cut).runs.size() == 1);
  REQUIRE(read_runs_jsonl(cut).size() == 1);  // what --resume keeps
}

TEST_CASE("a run whose child a signal ended is redone; a time-out or an error is not",
          "[sweep][runs]") {
  RunSpec s;
  s.dataset = "sphere";
  s.method = "hubo_2006";
  REQUIRE(killed_by_signal(killed_run(s, 9)));
  REQUIRE(killed_run(s, 11).error == "killed by signal 11");
  // The words alone do not make a killed run: the signal is a field of its own.
  REQUIRE(!killed_by_signal(failed_run(s, RunStatus::kFailed, "killed by signal 11")));
  REQUIRE(!killed_by_signal(failed_run(s, RunStatus::kFailed, "sphere: N = 0 is impossible")));
  REQUIRE(!killed_by_signal(failed_run(s, RunStatus::kTimeout, "exceeded the time limit of 1 s")));
  // As recorded in runs.jsonl and read back.
  const json written = killed_run(s, 9);
  REQUIRE(written["signal"] == 9);
  REQUIRE(killed_by_signal(written.get<RunResult>()));
}
