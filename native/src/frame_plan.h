// What a frame simulates and by which passes, made once from the settings: the renderer executes the plan and
// holds no rule of its own about which pass runs. A new effect is a new pass plus a line here.
#pragma once

#include "bounce/bounce.h"

namespace bounce {

struct FramePlan {
  enum class Direct { ShadowMaps, RayTraced };
  enum class Indirect { None, ForwardLightCuts, Ssvp, Topology };
  Direct direct = Direct::RayTraced;
  Indirect indirect = Indirect::None;
  bool indirect_shadows = false;  // the topology's clusters and gates shadow Forward Light Cuts' VPLs
  bool vpl_importance = false;    // SSVP draws its VPLs where shadow rays say their light reaches the view

  // Embree's copy of the scene: for ray-traced direct light, building the topology and tracing VPL importance.
  bool needs_cpu_scene() const { return direct == Direct::RayTraced || indirect_shadows || vpl_importance; }
};

inline FramePlan plan_frame(const BounceSettings& settings) {
  FramePlan plan;
  plan.direct = settings.shadow_method == BOUNCE_SHADOWS_RAY_TRACED ? FramePlan::Direct::RayTraced
                                                                    : FramePlan::Direct::ShadowMaps;
  switch (settings.method) {
    case BOUNCE_METHOD_FLC:
      plan.indirect = FramePlan::Indirect::ForwardLightCuts;
      plan.indirect_shadows = settings.flc_visibility != 0;
      break;
    case BOUNCE_METHOD_SSVP:
      plan.indirect = FramePlan::Indirect::Ssvp;
      plan.vpl_importance = settings.ssvp_importance != 0;
      break;
    case BOUNCE_METHOD_TOPOLOGY:
      plan.indirect = FramePlan::Indirect::Topology;
      break;
    default:  // DIRECT (AUTO renders with the explicit method of its plan: auto_plan.h)
      break;
  }
  return plan;
}

}  // namespace bounce
