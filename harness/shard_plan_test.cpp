#include "harness/shard_plan.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <numeric>

#include "core/error.hpp"
#include "harness/slurm.hpp"

using namespace pcrt;

namespace {

std::vector<RunSpec> render_runs(std::initializer_list<double> ns) {
  std::vector<RunSpec> runs;
  for (double n : ns) {
    RunSpec s;
    s.kind = RunKind::kRender;
    s.method = "reference_splat";
    s.N = n;
    s.M = 256.0;
    s.B = 1.0;
    runs.push_back(s);
  }
  return runs;
}

}  // namespace

TEST_CASE("shards balance estimated work, not run counts", "[shards]") {
  // One expensive run and many cheap ones: every n-th run would put the expensive run beside a
  // quarter of the cheap ones; the plan gives it a shard of its own.
  std::vector<double> costs(13, 1.0);
  costs[0] = 12.0;
  const ShardPlan plan = plan_shards(costs, 2);
  REQUIRE(plan.shards[0] == std::vector<size_t>{0});
  REQUIRE(plan.shards[1].size() == 12);
  REQUIRE(plan.cost[0] == Approx(12.0));
  REQUIRE(plan.cost[1] == Approx(12.0));
}

TEST_CASE("every run lands in exactly one shard, whatever the count", "[shards]") {
  std::vector<double> costs;
  for (int i = 0; i < 57; ++i) costs.push_back(1.0 + (i * 37 % 11));
  for (size_t n : {1, 2, 3, 4, 7, 57, 80}) {
    const ShardPlan plan = plan_shards(costs, n);
    REQUIRE(plan.shards.size() == n);
    std::vector<size_t> all;
    for (const auto& s : plan.shards) all.insert(all.end(), s.begin(), s.end());
    std::sort(all.begin(), all.end());
    std::vector<size_t> want(costs.size());
    std::iota(want.begin(), want.end(), size_t(0));
    REQUIRE(all == want);
    // Longest first to the least loaded: no shard exceeds the mean by more than the largest run.
    const double mean = std::accumulate(costs.begin(), costs.end(), 0.0) / double(n);
    for (double c : plan.cost) REQUIRE(c <= mean + 11.0 + 1e-9);
  }
}

TEST_CASE("run costs grow with the work a run does", "[shards]") {
  const std::vector<RunSpec> runs = render_runs({1000, 4000, 16000});
  const std::vector<double> c = run_costs(runs, {});
  REQUIRE(c[0] < c[1]);
  REQUIRE(c[1] < c[2]);
  RunSpec skew;
  skew.kind = RunKind::kReconstruct;
  skew.reconstruction = "delaunay";
  skew.dataset = "skew_lines";
  skew.N = 3200.0;
  RunSpec ball = skew;
  ball.dataset = "ball";
  REQUIRE(model_run_cost(skew) > 10 * model_run_cost(ball));  // (N/2)^2 cells against N log N
}

TEST_CASE("an earlier sweep's times replace the model and scale it", "[shards]") {
  const std::vector<RunSpec> runs = render_runs({1000, 4000, 16000});
  const double m0 = model_run_cost(runs[0]), m2 = model_run_cost(runs[2]);
  RunResult earlier;
  earlier.spec = runs[0];
  earlier.wall_s = 10 * m0;
  const std::vector<double> c = run_costs(runs, {earlier});
  REQUIRE(c[0] == Approx(10 * m0));
  REQUIRE(c[2] == Approx(10 * m2));  // scaled by the one measured ratio
}

TEST_CASE("a plan file gives each shard its runs and refuses another config", "[shards]") {
  const std::vector<RunSpec> runs = render_runs({1000, 2000, 4000, 8000});
  const ShardPlan plan = plan_shards(run_costs(runs, {}), 2);
  const json file = json::parse(plan_json(plan, runs, "model").dump());
  REQUIRE(plan_shard(file, runs, 1, 2, "plan.json") == plan.shards[1]);
  REQUIRE_THROWS_AS(plan_shard(file, runs, 0, 3, "plan.json"), InputError);
  const std::vector<RunSpec> other = render_runs({1000, 2000, 4000, 9000});
  const size_t holder = std::count(plan.shards[0].begin(), plan.shards[0].end(), 3) ? 0 : 1;
  REQUIRE_THROWS_AS(plan_shard(file, other, holder, 2, "plan.json"), InputError);
  // A config run no shard plans would never run: refused whichever shard asks (issue 29).
  const std::vector<RunSpec> more = render_runs({1000, 2000, 4000, 8000, 16000});
  for (size_t shard = 0; shard < 2; ++shard)
    REQUIRE_THROWS_WITH(plan_shard(file, more, shard, 2, "plan.json"),
                        "plan.json: plans 4 of the config's 5 runs; the others would never run");
}

TEST_CASE("Slurm job states parse into types", "[slurm]") {
  REQUIRE(parse_job_state("PENDING") == JobState::Pending);
  REQUIRE(parse_job_state("CANCELLED by 0") == JobState::Cancelled);
  REQUIRE(parse_job_state("OUT_OF_MEMORY") == JobState::OutOfMemory);
  REQUIRE(parse_job_state("BOOT_FAIL") == JobState::Failed);
  REQUIRE(job_state_name(JobState::NodeFail) == "NODE_FAIL");
  REQUIRE(is_active(JobState::Requeued));
  REQUIRE(!is_active(JobState::Completed));
  REQUIRE(is_failure(JobState::Timeout));
  REQUIRE(!is_failure(JobState::Gone));
  REQUIRE(!is_failure(JobState::Completed));
}

// Issue 29: a hand-edited or cut plan.json was an internal error ("shards": [1e30] undefined).
TEST_CASE("a plan file has every field checked, naming the file and the field", "[shards]") {
  const std::vector<RunSpec> runs = render_runs({1000, 2000, 4000});
  const json good = plan_json(plan_shards(run_costs(runs, {}), 2), runs, "model");
  REQUIRE(read_plan(good, "plan.json").size() == 2);
  const std::pair<const char*, const char*> bad[] = {
      {"", "[]"},
      {"", "{}"},
      {"/shards", "3"},
      {"/shards", "[]"},
      {"/shards", "[1e30]"},
      {"/shards", "[[{\"runs\": []}]]"},
      {"/shards/0/runs", "{}"},
      {"/shards/0/estimated_s", "-1"},
      {"/shards/0/estimated_s", "\"soon\""},
      {"/shards/0/runs/0", "\"a run\""},
      {"/shards/0/runs/0/reps", "-5"},
      {"/shards/0/runs/0/reps", "1e30"},
      {"/shards/0/runs/0/threads", "2.5"},
      {"/shards/0/runs/0/seed", "-1"},
      {"/shards/0/runs/0/N", "1e30"},
      {"/shards/0/runs/0/kind", "7"},
      {"/cost_source", "5"},
  };
  for (const auto& [path, value] : bad) {
    CAPTURE(path, value);
    json plan = good;
    plan[json::json_pointer(path)] = json::parse(value);
    try {
      (void)read_plan(plan, "DIR/plan.json");
      FAIL("accepted");
    } catch (const InputError& e) {
      REQUIRE(std::string(e.what()).find("DIR/plan.json") == 0);
    }
  }
  json twice = good;
  twice["shards"][1]["runs"].push_back(twice["shards"][0]["runs"][0]);
  REQUIRE_THROWS_WITH(read_plan(twice, "plan.json"),
                      Catch::Matchers::Contains("also planned in shard 0"));
}
