#include "harness/catalogue.hpp"

#include "core/dataset.hpp"
#include "harness/claims.hpp"
#include "harness/command_helpers.hpp"
#include "methods/method.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

json iteration_json(const IterationCounters& it) {
  if (!it.steps || !it.runs) return nullptr;
  return {{"steps", registered_counters()[it.steps->id()].name},
          {"runs", registered_counters()[it.runs->id()].name}};
}

std::string counter_name(const Counter* c) {
  return c ? registered_counters()[c->id()].name : std::string();
}

json design_json(const MethodInfo::ClaimDesign& d) {
  json metric = json::array();
  for (const Counter* c : d.metric) metric.push_back(counter_name(c));
  json fixed = json::object();
  for (const auto& [name, value] : d.fixed) fixed[name] = value;
  return {{"claim", d.claim},
          {"experiment", d.experiment},
          {"structure", d.structure},
          {"variable", d.variable},
          {"param", d.param},
          {"values", d.values},
          {"N", d.N},
          {"M", d.M},
          {"B", d.B},
          {"Ns", d.Ns},
          {"build", d.build},
          {"timed", d.timed},
          {"free", d.free},
          {"metric", metric},
          {"per", counter_name(d.per)},
          {"x", d.x},
          {"max", d.max},
          {"fixed", fixed},
          {"replicates", d.replicates},
          {"shapes", d.shapes}};
}

json real_time_json(const MethodInfo& m) {
  json designs = json::array();
  for (const MethodInfo::RealTimeDesign& r : m.real_time_designs)
    designs.push_back(
        {{"experiment", r.experiment}, {"N", r.N}, {"repetitions", r.repetitions}, {"why", r.why}});
  return designs;
}

json method_json(const MethodInfo& m) {
  json designs = json::array();
  for (const MethodInfo::ClaimDesign& d : m.designs) designs.push_back(design_json(d));
  json claims = json::array();
  for (const auto& c : m.claims)
    claims.push_back({{"quantity", c.quantity},
                      {"complexity", c.complexity},
                      {"variables", c.variables},
                      {"source", c.source}});
  json work = json::array();
  for (const Counter* c : m.work) work.push_back(registered_counters()[c->id()].name);
  return {{"id", m.id},
          {"paper", m.paper},
          {"thesis_ref", m.thesis_ref},
          {"description", m.description},
          {"structure", m.own_structure.empty() ? m.structure : m.own_structure},
          {"own_structure", !m.own_structure.empty()},
          {"needs", m.needs},
          {"parameters", params_json(m.params)},
          {"claims", claims},
          {"work_counters", work},
          {"real_time_claim", m.real_time_claim},
          {"iterative_claim", m.iterative_claim},
          {"iteration_counters", iteration_json(m.iterations)},
          {"hits_counter", counter_name(m.hits)},
          {"own_items", m.own_items},
          // Prepares from a stream (`pcrt render --stream`) for some of its parameters.
          {"streams", bool(m.stream_bytes_per_point)},
          {"designs", designs},
          {"real_time_designs", real_time_json(m)}};
}

json claim_json(const Claim& c) {
  return {{"id", c.id},
          {"subject", c.subject},
          {"statement", c.statement},
          {"complexity", c.complexity},
          {"variables", c.variables},
          {"source", c.source},
          {"tested", c.not_tested.empty()},
          {"not_tested", c.not_tested},
          {"about", claim_about_name(c.about)},
          {"precondition", c.precondition == Precondition::kUniformVolume
                               ? "a uniformly distributed cloud (ball or cube)"
                               : ""}};
}

}  // namespace

json catalogue_json() {
  json j = {{"methods", json::array()},      {"structures", json::array()},
            {"generators", json::array()},   {"reconstructions", json::array()},
            {"mesh_engines", json::array()}, {"claims", json::array()},
            {"counters", json::array()}};
  for (const MethodInfo& m : MethodRegistry::instance().all())
    j["methods"].push_back(method_json(m));
  for (const StructureInfo& s : StructureRegistry::instance().all())
    j["structures"].push_back({{"id", s.id},
                               {"description", s.description},
                               {"build_claim", s.build_claim},
                               {"query_claim", s.query_claim},
                               {"parameters", params_json(s.params)}});
  for (const GeneratorInfo& g : generators())
    j["generators"].push_back(
        {{"id", g.name}, {"description", g.description}, {"parameters", params_json(g.params)}});
  for (const Claim& c : all_claims()) j["claims"].push_back(claim_json(c));
  for (const ReconstructionInfo& r : ReconstructionRegistry::instance().all())
    j["reconstructions"].push_back(
        {{"id", r.id}, {"description", r.description}, {"claim", r.claim}});
  for (const MeshEngineInfo& e : MeshEngineRegistry::instance().all())
    j["mesh_engines"].push_back({{"id", e.id}, {"description", e.description}});
  for (size_t i = 0; i < registered_counter_count(); ++i)
    j["counters"].push_back({{"name", registered_counters()[i].name},
                             {"description", registered_counters()[i].description}});
  return j;
}

}  // namespace pcrt
