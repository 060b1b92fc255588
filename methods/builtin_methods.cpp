// Every method pcrt ships, listed once: a new method adds its register function here (and its
// folder to methods/CMakeLists.txt). See core/registry.hpp.
#include "methods/method.hpp"

namespace pcrt {

void register_adams_2005(MethodRegistry& registry);
void register_adamson_alexa_2003(MethodRegistry& registry);
void register_cai_2011(MethodRegistry& registry);
void register_cai_2015(MethodRegistry& registry);
void register_embree_oriented_disc(MethodRegistry& registry);
void register_ever_2024(MethodRegistry& registry);
void register_goradia_2010(MethodRegistry& registry);
void register_goradia_2011(MethodRegistry& registry);
void register_grt_2024(MethodRegistry& registry);
void register_hubo_2006(MethodRegistry& registry);
void register_hubo_2007(MethodRegistry& registry);
void register_kashyap_2010_implicit(MethodRegistry& registry);
void register_kashyap_2010_splat(MethodRegistry& registry);
void register_linsen_2007(MethodRegistry& registry);
void register_reference_splat(MethodRegistry& registry);
void register_schaufler_jensen_2000(MethodRegistry& registry);
void register_tejada_2006(MethodRegistry& registry);
void register_tejada_2007(MethodRegistry& registry);
void register_wald_seidel_2005(MethodRegistry& registry);
void register_wand_strasser_2003(MethodRegistry& registry);

void register_builtins(MethodRegistry& registry) {
  register_adams_2005(registry);
  register_adamson_alexa_2003(registry);
  register_cai_2011(registry);
  register_cai_2015(registry);
  register_embree_oriented_disc(registry);
  register_ever_2024(registry);
  register_goradia_2010(registry);
  register_goradia_2011(registry);
  register_grt_2024(registry);
  register_hubo_2006(registry);
  register_hubo_2007(registry);
  register_kashyap_2010_implicit(registry);
  register_kashyap_2010_splat(registry);
  register_linsen_2007(registry);
  register_reference_splat(registry);
  register_schaufler_jensen_2000(registry);
  register_tejada_2006(registry);
  register_tejada_2007(registry);
  register_wald_seidel_2005(registry);
  register_wand_strasser_2003(registry);
}

}  // namespace pcrt
