// What a frame simulates and by which passes, made once from the settings: the renderer executes the plan and
// holds no rule of its own about which pass runs. A new effect is a new pass plus a line here.
#pragma once

#include <algorithm>

#include "bounce/bounce.h"

namespace bounce {

struct FramePlan {
  enum class Direct { ShadowMaps, RayTraced };
  enum class Indirect { None, ForwardLightCuts, Ssvp, Topology };
  enum class NearField { None, RayTraced, FromGBuffer };
  Direct direct = Direct::RayTraced;
  Indirect indirect = Indirect::None;
  int bounces = 0;                // diffuse bounces simulated: the paper's one for FLC, SSVP two at most
  bool indirect_shadows = false;  // the topology's clusters and gates shadow Forward Light Cuts' VPLs
  float ray_checks = 0.0f;        // the share of light-pixel pairs a shadow ray checks (FLC's rule, SSVP's maps)
  int vpl_candidates = 1;         // Forward Light Cuts' VPLs drawn per VPL kept by its light, once rays have lit them
  bool vpl_importance = false;    // SSVP draws its VPLs where shadow rays say their light reaches the view
  // The GL VPL methods' distance clamp takes the first bounce's light next to lit surfaces; the near field gives it
  // back: by Embree rays with the ray-traced direct light, else marched through the G-buffer (which misses
  // surfaces the camera does not see). Blurred over near_field_blur pixels, as the method blurs its indirect light.
  NearField near_field = NearField::None;
  // The bounces whose share the near field gives back: the second's too where the method has one and rays meet
  // the surfaces (where the camera does not see them, the G-buffer has none of their light).
  int near_field_bounces = 0;
  float near_field_clamp = 0.0f;  // a fraction of the scene's radius
  int near_field_blur = 0;

  // The sample's world directions are drawn where their light reaches the view (cpu/world_reach.h), where the
  // world's light comes from those shared directions (SSVP's reflective shadow maps; shadow-mapped direct light
  // and the Forward Light Cuts VPLs it lights; ray-traced light draws directions per point) and Embree's copy of
  // the scene is there anyway.
  bool guide_world = false;

  // Embree's copy of the scene: for ray-traced direct light, the Topology method, building the topology, tracing
  // VPL importance and Ray Checks.
  bool needs_cpu_scene() const {
    return direct == Direct::RayTraced || indirect == Indirect::Topology || indirect_shadows || vpl_importance ||
           ray_checks > 0.0f;
  }
};

inline FramePlan plan_frame(const BounceSettings& settings) {
  FramePlan plan;
  plan.direct = settings.shadow_method == BOUNCE_SHADOWS_RAY_TRACED ? FramePlan::Direct::RayTraced
                                                                    : FramePlan::Direct::ShadowMaps;
  switch (settings.method) {
    case BOUNCE_METHOD_FLC:
      plan.indirect = FramePlan::Indirect::ForwardLightCuts;
      plan.bounces = 1;
      plan.indirect_shadows = settings.flc_visibility != 0;
      plan.ray_checks = plan.indirect_shadows ? std::clamp(settings.flc_ray_checks, 0.0f, 1.0f) : 0.0f;
      plan.vpl_candidates = plan.direct == FramePlan::Direct::RayTraced ? settings.flc_vpl_candidates : 1;
      plan.near_field_clamp = settings.flc_epsilon;
      plan.near_field_blur = settings.flc_blur_radius;
      break;
    case BOUNCE_METHOD_SSVP:
      plan.indirect = FramePlan::Indirect::Ssvp;
      plan.bounces = std::min(settings.bounces, 2);
      plan.vpl_importance = settings.ssvp_importance != 0;
      plan.ray_checks = std::clamp(settings.ssvp_ray_checks, 0.0f, 1.0f);
      plan.near_field_clamp = settings.ssvp_distance_clamp;
      plan.near_field_blur = settings.ssvp_blur_radius;
      break;
    case BOUNCE_METHOD_TOPOLOGY:
      plan.indirect = FramePlan::Indirect::Topology;
      plan.bounces = settings.bounces;
      break;
    default:  // DIRECT (AUTO renders with the explicit method of its plan: auto_plan.h)
      break;
  }
  plan.guide_world =
      (plan.indirect == FramePlan::Indirect::Ssvp ||
       (plan.indirect == FramePlan::Indirect::ForwardLightCuts && plan.direct == FramePlan::Direct::ShadowMaps)) &&
      plan.needs_cpu_scene();
  if (plan.near_field_clamp > 0.0f) {
    plan.near_field = plan.direct == FramePlan::Direct::RayTraced ? FramePlan::NearField::RayTraced
                                                                  : FramePlan::NearField::FromGBuffer;
    plan.near_field_bounces = plan.near_field == FramePlan::NearField::RayTraced ? plan.bounces : 1;
  }
  return plan;
}

}  // namespace bounce
