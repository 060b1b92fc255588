// What each pcrt command is told: one typed struct per command, its defaults written here once.
// harness/cli.cpp binds every field to its option (name, help text, range) with CLI11, in a
// function of the same shape per command (`bind(CLI::App&, RenderOptions&)`), and `pcrt CMD
// --help` shows these defaults; the commands (commands.hpp) take the struct. An optional field is
// one whose absence means something ("not given"), so a default cannot stand in for it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "render/renderer.hpp"

namespace pcrt {

// The triangle engine --engine and --truth-engine use when not given.
inline constexpr const char* kDefaultMeshEngine = "bvh";

// What render, trace, accuracy and compare trace: a point method on a dataset, or a triangle mesh.
struct SceneArgs {
  std::optional<std::string> method;  // --method ID
  std::optional<std::string> data;    // --data DATA: a file or a generator spec
  std::optional<std::string> mesh;    // --mesh FILE: a triangle mesh instead of a point method
  std::optional<std::string> engine;  // --engine ID, with --mesh only (kDefaultMeshEngine)
  std::string structure;              // --structure ID; empty: the method's paper's
  ParamValues set;                    // --set NAME=VALUE (repeatable; each name once)
  int threads = 0;                    // --threads N; 0: all cores
};

struct InfoOptions {
  static constexpr const char* usage = "pcrt info DATA [--json]";
  std::string data;
  bool json = false;
  int threads = 0;
};

struct RenderOptions {
  static constexpr const char* usage =
      "pcrt render (--method ID --data DATA | --mesh FILE [--engine ID] | --scene FILE.json) "
      "--out FILE.png|.exr [options]";
  SceneArgs scene;
  std::optional<std::string> scene_file;  // --scene FILE.json: objects, materials, lights, camera
  std::string out;
  RenderSettings settings;  // --width ... --ray-epsilon, with the renderer's own defaults
  std::optional<std::string> depth, normals, stats;
  bool stream = false;  // --stream: the generator's points go straight into the method
  bool view_given = false, up_given = false;  // refused with a scene file that has a camera
};

struct TraceOptions {
  static constexpr const char* usage =
      "pcrt trace (--method ID --data DATA | --mesh FILE [--engine ID]) --rays RAYS.csv "
      "--out HITS.csv [options]";
  SceneArgs scene;
  std::string rays, out;
  std::optional<std::string> stats;
};

// The mesh accuracy and compare judge against, and how the cloud is sampled on it.
struct TruthArgs {
  std::optional<std::string> mesh;    // --truth MESH
  std::optional<std::string> sample;  // --sample SPEC (parse_mesh_sampling has the defaults)
  std::optional<std::string> engine;  // --truth-engine ID (kDefaultMeshEngine)
};

struct AccuracyOptions {
  static constexpr const char* usage =
      "pcrt accuracy (--method ID [--structure ID] | --reconstruction ID [--engine ID]) "
      "(--data GENERATOR_SPEC | --truth MESH [--sample SPEC]) [--rays N] [--json]";
  SceneArgs scene;  // --engine: the reconstruction's triangle engine
  size_t rays = 20000;
  uint64_t seed = 1;
  std::optional<std::string> reconstruction;
  TruthArgs truth;
  size_t secondary = 0;
  bool json = false;
};

struct CompareOptions {
  static constexpr const char* usage =
      "pcrt compare --method ID --truth MESH [--sample SPEC] --out DIFF.png [options]";
  SceneArgs scene;  // --data, --mesh and --engine are refused: the cloud comes from --truth
  TruthArgs truth;
  std::string out;
  std::optional<std::string> images;
  int width = 256, height = 256;
  uint64_t seed = 1;
  Vec3 view = RenderSettings{}.view, up = RenderSettings{}.up;
  bool json = false;
};

struct AnchorOptions {
  static constexpr const char* usage =
      "pcrt anchor (--data DATA | --mesh MESH.ply) [--method M] [--structure S] [--set "
      "NAME=VALUE] [--width W --height H --threads T --reps R] [--json]";
  std::optional<std::string> data, mesh, method, structure;
  ParamValues set;
  int width = 512, height = 512, reps = 7, threads = 0;
  bool json = false;
};

struct ReconstructOptions {
  static constexpr const char* usage =
      "pcrt reconstruct --method delaunay|afsr --data DATA [--out MESH.ply] [--json]";
  std::string method, data;
  std::optional<std::string> out;
  int threads = 0;
  bool json = false;
};

struct CrossoverOptions {
  static constexpr const char* usage =
      "pcrt crossover --data DATA --method ID [--structure ID] [--reconstruction ID] "
      "[--engine ID] [--width W --height H --spp S --bounces B --reps R --frames F] [--json]";
  std::string data, method, structure;
  std::string reconstruction = "afsr";
  std::string engine = kDefaultMeshEngine;
  RenderSettings settings;  // --width, --height, --spp, --bounces
  int reps = 3;
  long long frames = 100;
  int threads = 0;
  bool json = false;
};

struct FurnaceOptions {
  static constexpr const char* usage =
      "pcrt furnace (--method ID (--data DATA | --truth MESH [--sample SPEC]) | --mesh FILE "
      "[--engine ID] | --exact --data GENERATOR_SPEC) [--bounces B] [--spp S] [--json]";
  SceneArgs scene;
  TruthArgs truth;
  RenderSettings settings = [] {
    RenderSettings s;
    s.width = s.height = 128;
    s.spp = 4;
    return s;
  }();
  std::optional<std::string> out;  // the furnace image
  bool exact = false;              // trace the generator's exact surface instead of a method
  bool json = false;
};

struct ListOptions {
  static constexpr const char* usage = "pcrt list [--json]";
  bool json = false;
};

struct ConvertOptions {
  static constexpr const char* usage = "pcrt convert DATA --out FILE.ply [--ascii]";
  std::string data, out;
  bool ascii = false;
};

// --shard i/n: shard `index` (0-based) of `count`.
struct ShardIndex {
  size_t index = 0, count = 1;
};

// The most shards a sweep is split into: pcrt cluster submit --shards, pcrt sweep --shard i/n and
// a plan file's "shards".
constexpr size_t kMaxShards = 100000;

struct SweepOptions {
  static constexpr const char* usage =
      "pcrt sweep CONFIG.json [--out DIR] [--resume | --overwrite] [--shard i/n [--costs DIR | "
      "--plan FILE]] [--fit]";
  std::string config;
  std::optional<std::string> out;  // default results/<config name>
  bool resume = false;
  bool overwrite = false;  // an earlier sweep's files in DIR are moved to DIR/previous.N
  std::optional<ShardIndex> shard;
  std::optional<std::string> costs, plan;
  bool fit = false;
  bool no_limit = false;  // run a sweep over kMaxSweepRuns or kMaxSweepSeconds anyway
  // What a sweep may plan without --no-limit: a config that expands past either is a mistake
  // more often than a plan (a grid of 10^6 points, N = 10^9 per run).
  static constexpr size_t kMaxSweepRuns = 100000;
  static constexpr double kMaxSweepSeconds = 7 * 24 * 3600.0;
};

struct MergeOptions {
  static constexpr const char* usage = "pcrt merge DIR... --out DIR [--keep-partial] [--overwrite]";
  std::vector<std::string> dirs;
  std::string out;
  bool keep_partial = false;  // merge shards that miss runs, saying what is missing
  bool overwrite = false;     // an earlier merge's files in --out are moved to previous.N
};

struct FitOptions {
  static constexpr const char* usage = "pcrt fit DIR";
  std::string dir;
};

struct ReportOptions {
  static constexpr const char* usage = "pcrt report DIR";
  std::string dir;
};

struct CalibrateOptions {
  static constexpr const char* usage = "pcrt calibrate [--out DIR] [--json]";
  std::optional<std::string> out;  // default: a temporary directory, removed
  bool json = false;
};

struct CheckOptions {
  static constexpr const char* usage =
      "pcrt check --config CONFIG.json --baseline BASELINE.json [--tolerance P] [--update] "
      "[--out DIR]";
  std::string config, baseline;
  double tolerance = 0;  // percent
  bool update = false;
  std::optional<std::string> out;  // default: a temporary directory, removed
};

struct ClusterSubmitOptions {
  static constexpr const char* usage =
      "pcrt cluster submit CONFIG.json --out DIR --shards N [options] | pcrt cluster submit "
      "--resume DIR";
  std::string target;  // CONFIG.json, or with --resume the DIR of a first submission
  std::optional<std::string> out;
  std::optional<size_t> shards;
  std::optional<std::string> partition, time, cpus_per_task, mem;
  std::vector<std::string> sbatch_args;
  std::optional<std::string> costs;
  bool resume = false, dry_run = false;
};

struct ClusterStatusOptions {
  static constexpr const char* usage = "pcrt cluster status DIR";
  std::string dir;
};

// `pcrt _run SPEC [PARENT_PID]`: one sweep run in a child process (internal).
struct RunOneOptions {
  static constexpr const char* usage = "pcrt _run SPEC_JSON [PARENT_PID]";
  std::string spec;
  std::optional<std::string> parent_pid;
};

// Every command's options, as the command line filled them.
struct AllOptions {
  InfoOptions info;
  RenderOptions render;
  TraceOptions trace;
  FurnaceOptions furnace;
  AccuracyOptions accuracy;
  CompareOptions compare;
  AnchorOptions anchor;
  ReconstructOptions reconstruct;
  CrossoverOptions crossover;
  SweepOptions sweep;
  MergeOptions merge;
  FitOptions fit;
  ReportOptions report;
  CalibrateOptions calibrate;
  CheckOptions check;
  ListOptions list;
  ConvertOptions convert;
  ClusterSubmitOptions cluster_submit;
  ClusterStatusOptions cluster_status;
  RunOneOptions run_one;
};

}  // namespace pcrt
