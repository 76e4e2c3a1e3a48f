/* Bounce: the C API of the native core.
 *
 * Conventions
 *   - Every function returns a BounceStatus (or, for getters, a value documented per function). On failure
 *     bounce_last_error() explains what went wrong, naming the argument or object at fault. The error text is
 *     per thread and stays valid until the next failing call on that thread.
 *   - No C++ exception crosses this boundary.
 *   - Handles are opaque. bounce_engine_destroy(NULL) is a no-op.
 *   - Arrays passed in are copied before the call returns; the caller keeps ownership.
 *   - Units: metres, radians, linear Rec.709 RGB. Light quantities are radiometric and already converted from
 *     the host application's units (see BounceLight).
 *   - Matrices: 16 floats, column-major (OpenGL convention), as Blender's Matrix transposed.
 *
 * Threading
 *   Each engine owns one render thread, which owns a headless EGL OpenGL 4.5 core context; every GL call is
 *   made there. API calls may come from any thread, one at a time per engine: scene edits are queued to the
 *   render thread and applied before the next render; bounce_render_start() returns at once and the render
 *   runs in the background. Several engines may exist at once.
 */
#ifndef BOUNCE_BOUNCE_H
#define BOUNCE_BOUNCE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define BOUNCE_API __declspec(dllexport)
#else
#define BOUNCE_API __attribute__((visibility("default")))
#endif

#define BOUNCE_API_VERSION 13

typedef enum BounceStatus {
  BOUNCE_OK = 0,
  BOUNCE_ERROR_INVALID_ARGUMENT = 1, /* a null pointer, an out-of-range value, an unknown key */
  BOUNCE_ERROR_CONTEXT = 2,          /* no OpenGL 4.5 context could be made (EGL, driver) */
  BOUNCE_ERROR_GL = 3,               /* an OpenGL failure: shader compile, framebuffer, out of GPU memory */
  BOUNCE_ERROR_OUT_OF_MEMORY = 4,
  BOUNCE_ERROR_NOT_READY = 5, /* no finished frame yet, or a render is running */
  BOUNCE_ERROR_CANCELLED = 6,
  BOUNCE_ERROR_INTERNAL = 7,
  BOUNCE_ERROR_RAY_TRACING = 8 /* Embree could not start (ray-traced shadows, Topology, Auto need it) */
} BounceStatus;

/* ---- Library ----------------------------------------------------------------------------------------- */

BOUNCE_API const char* bounce_version(void);    /* "MAJOR.MINOR.PATCH" */
BOUNCE_API int32_t bounce_api_version(void);    /* BOUNCE_API_VERSION of the built library */
BOUNCE_API const char* bounce_last_error(void); /* "" when the last call on this thread succeeded */

/* ---- Settings (one table: settings.def) -------------------------------------------------------------- */

#define BOUNCE_SETTING_VIEWPORT 1
#define BOUNCE_SETTING_PIXEL 2
#define BOUNCE_SETTING_FACTOR 4
#define BOUNCE_SETTING_ANGLE 8

typedef struct BounceSettings {
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  ctype name;
#include "settings.def"
#undef BOUNCE_SETTING
} BounceSettings;

typedef enum BounceMethod {
  BOUNCE_METHOD_AUTO = 0,
  BOUNCE_METHOD_DIRECT = 1,
  BOUNCE_METHOD_FLC = 2,
  BOUNCE_METHOD_SSVP = 3,
  BOUNCE_METHOD_TOPOLOGY = 4
} BounceMethod;

typedef enum BounceShadowMethod { BOUNCE_SHADOWS_MAPS = 0, BOUNCE_SHADOWS_RAY_TRACED = 1 } BounceShadowMethod;

BOUNCE_API size_t bounce_settings_size(void);
BOUNCE_API void bounce_settings_defaults(BounceSettings* out);
/* JSON array, one object per setting in struct order: name, type, kind, label, default, min, max, soft_min,
 * soft_max, flags, group, items [[id, label, tooltip], ...], description. Static storage. */
BOUNCE_API const char* bounce_settings_table_json(void);
/* Checks ranges; the message names the setting at fault. */
BOUNCE_API BounceStatus bounce_settings_validate(const BounceSettings* settings);

/* ---- Engine ------------------------------------------------------------------------------------------ */

typedef struct BounceEngine BounceEngine;

typedef struct BounceEngineDesc {
  /* EGL platform: NULL or "" = the BOUNCE_EGL_PLATFORM environment variable, else "surfaceless" (Mesa),
   * else "device" (EGL_EXT_platform_device, for headless NVIDIA). */
  const char* egl_platform;
  int32_t debug_gl; /* nonzero: GL debug output into the log */
} BounceEngineDesc;

/* Starts the render thread and makes its GL context; fails with BOUNCE_ERROR_CONTEXT and the EGL reason. */
BOUNCE_API BounceStatus bounce_engine_create(const BounceEngineDesc* desc, BounceEngine** out);
/* Cancels any render, frees GPU objects on the render thread, joins it. */
BOUNCE_API void bounce_engine_destroy(BounceEngine* engine);
/* Renderer and version strings of the context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) | 4.5 (Core Profile)". */
BOUNCE_API BounceStatus bounce_engine_gl_info(BounceEngine* engine, char* buffer, size_t buffer_size);

/* ---- Scene ------------------------------------------------------------------------------------------- */

/* Geometry of one mesh in its object space. Meshes are keyed by the caller (e.g. a hash of the evaluated
 * mesh) and shared by every instance that draws them. Non-finite positions, degenerate triangles and triangles
 * out of range are dropped and counted in BounceSceneStats, not fatal. */
typedef struct BounceMeshDesc {
  uint32_t vertex_count;
  const float* positions; /* 3 * vertex_count */
  uint32_t triangle_count;
  const uint32_t* triangles;     /* 3 * triangle_count vertex indices */
  const float* corner_normals;   /* 9 * triangle_count (split normals), or NULL for flat normals */
  const float* corner_uvs;       /* 6 * triangle_count, or NULL */
  const int32_t* triangle_slots; /* triangle_count material slot indices, or NULL for slot 0 */
} BounceMeshDesc;

BOUNCE_API BounceStatus bounce_mesh_set(BounceEngine* engine, uint64_t mesh_key, const BounceMeshDesc* mesh);
BOUNCE_API BounceStatus bounce_mesh_remove(BounceEngine* engine, uint64_t mesh_key);

typedef enum BounceTextureFormat {
  BOUNCE_TEXTURE_RGBA8_SRGB = 0, /* 8-bit, sRGB-encoded colour, linear alpha */
  BOUNCE_TEXTURE_RGBA8_LINEAR = 1,
  BOUNCE_TEXTURE_RGBA32F = 2 /* linear float */
} BounceTextureFormat;

/* Pixels bottom row first (Blender's order), 4 channels. */
BOUNCE_API BounceStatus bounce_texture_set(BounceEngine* engine, uint64_t texture_key, int32_t width, int32_t height,
                                           int32_t format, const void* pixels);
BOUNCE_API BounceStatus bounce_texture_remove(BounceEngine* engine, uint64_t texture_key);

#define BOUNCE_NO_TEXTURE 0u

typedef struct BounceMaterial {
  float base_color[3];         /* linear albedo, multiplied with the texture */
  float alpha;                 /* multiplied with the texture alpha when alpha_from_texture */
  uint64_t base_color_texture; /* texture key or BOUNCE_NO_TEXTURE */
  int32_t alpha_from_texture;  /* the base-colour texture's alpha drives a cut-out */
  float alpha_threshold;       /* cut-out: a surface point exists where alpha >= threshold */
  float emission[3];           /* emitted radiance, colour * strength (W/m^2/sr), seen by the camera */
  int32_t double_sided;        /* reserved, 1 */
  uint64_t emission_texture;   /* texture key or BOUNCE_NO_TEXTURE: its colour multiplies emission (as a light, each
                                  emissive triangle carries the texture's mean over the triangle) */
} BounceMaterial;

/* Replaces the whole material table. Instances refer to materials by index into it. */
BOUNCE_API BounceStatus bounce_materials_set(BounceEngine* engine, uint32_t count, const BounceMaterial* materials);

/* Replaces the whole instance list. Instance i draws mesh_keys[i] with transform matrices[16 i ...] (object to
 * world, column-major); its triangle with slot s uses material slot_materials[slot_offsets[i] + s], and slots
 * beyond slot_counts[i] use the default material (grey 0.8). */
typedef struct BounceInstancesDesc {
  uint32_t count;
  const uint64_t* mesh_keys;
  const float* matrices;
  const uint32_t* slot_offsets;
  const uint32_t* slot_counts;
  uint32_t slot_material_count;
  const uint32_t* slot_materials;
} BounceInstancesDesc;

BOUNCE_API BounceStatus bounce_instances_set(BounceEngine* engine, const BounceInstancesDesc* instances);

typedef enum BounceLightType {
  BOUNCE_LIGHT_POINT = 0,
  BOUNCE_LIGHT_SPOT = 1,
  BOUNCE_LIGHT_SUN = 2,
  BOUNCE_LIGHT_AREA_RECT = 3,    /* rectangle or square */
  BOUNCE_LIGHT_AREA_ELLIPSE = 4, /* disk or ellipse */
  BOUNCE_LIGHT_AREA_TRIANGLE = 5 /* two-sided; the core turns emissive triangles into these */
} BounceLightType;

/* A light in radiometric units (the add-on converts Blender's units, see addon/export/lights.py):
 *   point, spot: intensity = radiant intensity (W/sr) per channel; irradiance I cos / (d^2 + radius^2).
 *   spot:        times smoothstep((cos phi - cos half_angle) / ((1 - cos half_angle) blend)), phi the angle
 *                to the axis, and times cos phi when spot_cos_falloff is set (Blender 3.x).
 *   sun:         intensity = irradiance (W/m^2) on a surface facing the light; angle = angular diameter.
 *   area:        intensity = radiance (W/m^2/sr) of the Lambertian emitting side, which faces -axis_z.
 *                half_size = half extents along axis_x, axis_y (world units, object scale applied).
 *   triangle:    intensity = radiance of both sides; corners position and position + triangle[0..1], position +
 *                triangle[2..3] in (axis_x, axis_y) coordinates; axis_z is the triangle's normal. */
typedef struct BounceLight {
  int32_t type;
  int32_t cast_shadow;
  float position[3];
  float axis_x[3]; /* unit vectors of the light's frame; the light shines along -axis_z */
  float axis_y[3];
  float axis_z[3];
  float intensity[3];
  float radius;       /* point/spot soft radius */
  float half_size[2]; /* area */
  float spot_half_angle;
  float spot_blend;
  int32_t spot_cos_falloff;
  float sun_angle;
  float triangle[4]; /* triangle: its second and third corners in the light's frame (x, y), from position */
} BounceLight;

/* Replaces the whole light list. Lights with zero or non-finite intensity are skipped and counted, and so are
 * lights out of range (BounceSceneStats). */
BOUNCE_API BounceStatus bounce_lights_set(BounceEngine* engine, uint32_t count, const BounceLight* lights);

/* The world: radiance arriving from every direction, seen where no surface is hit and lighting the scene (see
 * BounceSettings.world_lights). Radiance toward direction d is background times, with an environment, the
 * texture at the equirectangular coordinates (Blender's: u = 0.5 - atan2(e.y, e.x) / 2 pi, v = atan2(e.z,
 * hypot(e.x, e.y)) / pi + 0.5) of e = world_to_environment * d. */
typedef struct BounceWorld {
  float background[3];           /* radiance, or the environment's factor (colour * strength) */
  int32_t transparent;           /* the camera sees colour 0 and alpha 0 where it sees the world (Film > Transparent) */
  uint64_t environment_texture;  /* a texture key (bounce_texture_set), or BOUNCE_NO_TEXTURE for a uniform world */
  float world_to_environment[9]; /* column-major 3x3 applied to a direction before the lookup (Mapping node) */
  int32_t camera_hidden;         /* the camera sees colour 0, alpha 1, where it sees the world (the world's Ray
                                    Visibility > Camera off); the world lights the scene all the same */
} BounceWorld;

BOUNCE_API BounceStatus bounce_world_set(BounceEngine* engine, const BounceWorld* world);

typedef struct BounceSceneStats {
  uint32_t mesh_count;
  uint32_t instance_count;
  uint64_t triangle_count;    /* drawn triangles, instances counted */
  uint64_t dropped_triangles; /* non-finite or zero-area triangles removed at upload */
  uint32_t light_count;
  uint32_t skipped_lights; /* zero, negative or non-finite intensity */
  uint32_t texture_count;
  uint64_t gpu_bytes; /* geometry + textures */
  float bounds_min[3];
  float bounds_max[3];
  /* The numeric range policy (native/src/scene_data.cpp): coordinates beyond 1e9 m from the origin and light
   * intensities beyond 1e15 are more than float32 rays, shadow maps and depth buffers resolve. */
  uint64_t out_of_range_triangles; /* a corner beyond 1e9 m: dropped */
  uint32_t out_of_range_instances; /* world bounds reaching beyond 1e9 m: not drawn */
  uint32_t out_of_range_lights;    /* point, spot or area lights beyond 1e9 m: skipped */
  uint32_t clamped_lights;         /* intensity dimmed to 1e15, or radius or size cut to 1e9 m */
} BounceSceneStats;

/* Waits until the queued scene edits are applied on the render thread, then fills the stats. */
BOUNCE_API BounceStatus bounce_scene_stats(BounceEngine* engine, BounceSceneStats* out);

/* ---- Camera and rendering ---------------------------------------------------------------------------- */

typedef struct BounceCamera {
  float world_to_view[16]; /* Blender's view matrix (camera matrix_world inverted) */
  float projection[16];    /* OpenGL clip-from-view, e.g. camera.calc_matrix_camera() or region window_matrix */
  int32_t width, height;   /* full image size in pixels */
  int32_t crop[4];         /* x0, y0, x1, y1 in pixels (bottom-left origin, exclusive end) of the part
                              to render; all zero = the whole image (render border) */
  int32_t frame;           /* frame number, mixed into the seed */
} BounceCamera;

typedef enum BounceAov {
  BOUNCE_AOV_COMBINED = 0,      /* RGBA: direct + indirect + emission + background */
  BOUNCE_AOV_DIRECT = 1,        /* RGB: direct diffuse light reflected (albedo included) */
  BOUNCE_AOV_EMISSION = 2,      /* RGB */
  BOUNCE_AOV_ALBEDO = 3,        /* RGB: diffuse colour */
  BOUNCE_AOV_NORMAL = 4,        /* XYZ: world-space shading normal */
  BOUNCE_AOV_DEPTH = 5,         /* Z: distance along the view axis (Blender's Depth pass); 1e10 for background */
  BOUNCE_AOV_INDIRECT = 6,      /* RGB: indirect diffuse light reflected (albedo included) */
  BOUNCE_AOV_VPLS = 7,          /* RGB: debug view of one sample's virtual point lights (FLC: coloured by level;
                                   SSVP: by cluster, with the cluster centres as large dots) */
  BOUNCE_AOV_SECOND_BOUNCE = 8, /* RGB: the second diffuse bounce alone, reflected (SSVP; part of Indirect) */
  BOUNCE_AOV_TOPOLOGY = 9,      /* RGBA: debug view of the topology (visibility clusters in colours, skeleton
                                   balls, gates as disks, per the topology_show_* settings); alpha = coverage */
  BOUNCE_AOV_COUNT = 10
} BounceAov;

BOUNCE_API int32_t bounce_aov_channels(int32_t aov); /* 4, 3 or 1; 0 for an unknown AOV */
BOUNCE_API const char* bounce_aov_name(int32_t aov); /* "Combined", "Direct", ... */
/* The AOVs a method writes, as bits 1 << aov: every method writes Combined, Direct, Emission, Albedo, Normal and
 * Depth; FLC and SSVP add Indirect and VPLs, SSVP Second Bounce, TOPOLOGY Indirect and Topology, AUTO Indirect and
 * Second Bounce (zero where its plan has none). A frame holds these only (large frames need the memory);
 * bounce_frame_read returns zeros for the others. */
BOUNCE_API uint32_t bounce_method_aovs(int32_t method);

/* Starts a render of settings->samples progressive samples (copied) in the background. A render already
 * running is cancelled first. */
BOUNCE_API BounceStatus bounce_render_start(BounceEngine* engine, const BounceSettings* settings,
                                            const BounceCamera* camera);
BOUNCE_API BounceStatus bounce_render_cancel(BounceEngine* engine);

typedef enum BounceRenderState {
  BOUNCE_RENDER_IDLE = 0,
  BOUNCE_RENDER_RUNNING = 1,
  BOUNCE_RENDER_DONE = 2,
  BOUNCE_RENDER_FAILED = 3,
  BOUNCE_RENDER_CANCELLED = 4
} BounceRenderState;

typedef struct BounceRenderProgress {
  int32_t state;        /* BounceRenderState */
  int32_t samples_done; /* of the render in progress or the last one */
  int32_t samples_total;
  float progress;        /* 0..1 over samples and tiles */
  uint64_t frame_serial; /* increments each time a readable frame is published */
  char stage[64];        /* what runs now when it is not sampling, e.g. "Topology: thinning" (precomputation,
                            whose share of `progress` comes first); "" otherwise */
} BounceRenderProgress;

BOUNCE_API BounceStatus bounce_render_progress(BounceEngine* engine, BounceRenderProgress* out);
/* Blocks until the render ends or timeout_ms passes (negative: no limit). Returns the render's own failure
 * (BOUNCE_ERROR_GL, ...) with its message, BOUNCE_ERROR_NOT_READY on timeout, BOUNCE_ERROR_CANCELLED. */
BOUNCE_API BounceStatus bounce_render_wait(BounceEngine* engine, int32_t timeout_ms);

#define BOUNCE_MAX_STAGES 16

typedef struct BounceStageTime {
  char name[32];
  double gpu_ms; /* GL timer queries, summed over samples and tiles */
  double cpu_ms; /* wall time on the render thread */
} BounceStageTime;

/* What AUTO's scene analysis found (native/src/cpu/scene_analysis.h): each component's estimated share of the
 * image the camera sees (the image's mean luminance; the shares and what the camera sees of emissive surfaces and
 * of the world add up to 1). Index 0 lamps, 1 the world, 2 emissive surfaces. */
typedef struct BounceLightShares {
  float direct[3];
  float first_bounce[3];
  float second_bounce;   /* every source */
  float emission_seen;   /* emissive surfaces in view */
  float background_seen; /* the world in view */
  float mean_albedo;     /* luminance of the albedo of the surfaces in view */
  float openness;        /* of the light paths leaving the surfaces in view, the share that escapes to the world */
  float analysis_ms;     /* what the analysis cost, when it ran for this render (it is kept while the scene and the
                            view stay put) */
} BounceLightShares;

typedef struct BounceFrameInfo {
  int32_t width, height; /* size of the published frame (the crop, if any) */
  int32_t samples;       /* samples averaged in it */
  uint64_t serial;
  int32_t stage_count;
  BounceStageTime stages[BOUNCE_MAX_STAGES];
  uint64_t nonfinite_pixels;    /* pixels with a NaN/Inf value in some AOV, which was zeroed (should be 0) */
  uint64_t vpl_count;           /* virtual point lights of the last sample (FLC, SSVP: both bounces) */
  uint64_t divergent_triangles; /* triangles the last sample sent to the tessellator (FLC) */
  int32_t main_light;           /* SSVP: the light whose bounce the last sample propagated (each sample draws one
                                   by its flux), as its index in bounce_lights_set's list; -1: none, or the world or
                                   an emissive surface */
  int32_t cluster_count;        /* SSVP: k-means clusters of the last sample; TOPOLOGY: visibility clusters */
  int32_t method;               /* the method that rendered the frame (AUTO's choice; never AUTO) */
  int32_t bounces;              /* the diffuse bounces it simulates: 0 for DIRECT, 1 for FLC, the bounces setting
                                   for TOPOLOGY and SSVP (2 at most) */
  char plan[512];               /* AUTO: what it simulated and left out, and why, in a few sentences; "" otherwise */
  BounceLightShares shares;     /* AUTO: the analysis the plan came from; zeros otherwise */
  float noise_relmse;           /* the noise its samples left, estimated as the benchmarks' relMSE (mean of
                                   (x - r)^2 / (r^2 + 0.01) over the RGB values of Combined, r the converged image):
                                   native/src/noise_estimate.h; -1 where unknown (one sample, or tiles that take
                                   turns: the tile_size setting) */
  float noise_direct_relmse;    /* the part of noise_relmse in the Direct pass, whose rays are stratified over each
                                   pixel's samples: it falls as samples^-noise_direct_rate, the rest as 1 / samples;
                                   0 where the frames did not hold the Direct pass */
  float noise_direct_rate;      /* that rate, measured from the Direct pass of three checkpoints: 1 to 3; 1 where
                                   unknown */
  float bias_relmse;            /* the error its settings accept in the same measure, which more samples do not
                                   remove: what they leave out, and the method's bias class on what it simulates
                                   (native/src/auto_plan.h); AUTO's plan always, an explicit method where it has
                                   Embree's copy of the scene (TOPOLOGY; ray-traced shadows, Indirect Shadows,
                                   VPL Importance: the defaults); -1 otherwise */
  uint32_t aovs;                /* the AOVs the frame holds, as bits 1 << aov: a render's last frame every AOV of
                                   its method (bounce_method_aovs); the partial frames before it Combined alone,
                                   which is what a progressive display shows, and Direct at the noise estimate's
                                   checkpoints, unless the method computes every AOV on the CPU (TOPOLOGY) */
} BounceFrameInfo;

/* The most recently published frame: after each progressive sample of a render (viewport) and at its end.
 * A partial frame may hold fewer AOVs than the last (BounceFrameInfo::aovs); bounce_frame_read returns zeros for
 * the others. The engine keeps that frame for bounce_frame_read until the next bounce_frame_info call. */
BOUNCE_API BounceStatus bounce_frame_info(BounceEngine* engine, BounceFrameInfo* out);
/* Copies one AOV of the frame the last bounce_frame_info call described (so a frame published in between, e.g.
 * of another size after a viewport resize, does not change what is read), rows bottom first, channels
 * interleaved: dst holds width * height * bounce_aov_channels(aov) floats. BOUNCE_ERROR_NOT_READY when
 * bounce_frame_info has not returned a frame yet. */
BOUNCE_API BounceStatus bounce_frame_read(BounceEngine* engine, int32_t aov, float* dst, size_t float_count);

/* ---- Topology (method TOPOLOGY) --------------------------------------------------------------------------- */

#define BOUNCE_TOPOLOGY_STAGES 6

/* The topology of the empty space the engine's last TOPOLOGY render used (built then, or found in the
 * process-wide cache). */
typedef struct BounceTopologyInfo {
  int32_t available; /* 0 until a TOPOLOGY render has run on this engine; the rest is then zero */
  int32_t grid[3];   /* voxels per axis */
  float voxel_size;  /* world units */
  uint32_t skeleton_nodes;
  uint32_t segmented_nodes;
  uint32_t clusters;                            /* visibility clusters */
  uint32_t gates;                               /* visibility gates */
  uint64_t builds;                              /* topologies built in this process so far (the cache's misses) */
  char stage_names[BOUNCE_TOPOLOGY_STAGES][24]; /* "voxelize", "distance transform", "thinning", ... */
  double stage_ms[BOUNCE_TOPOLOGY_STAGES];      /* precomputation wall time per stage, when it was built */
} BounceTopologyInfo;

BOUNCE_API BounceStatus bounce_topology_info(BounceEngine* engine, BounceTopologyInfo* out);

/* ---- Auto's cost model ------------------------------------------------------------------------------- */

/* Keeps Auto's cost model (what a sample costs on this machine, learned from the frames rendered) in `directory`
 * (created when needed), one file per device, read by the engines of later processes: a farm's `blender -b` runs
 * start from what the earlier ones on the machine measured. NULL or "" keeps it in memory only (the default).
 * Process-wide; a file that cannot be read or written is ignored. */
BOUNCE_API BounceStatus bounce_cost_model_directory(const char* directory);

#ifdef __cplusplus
}
#endif

#endif /* BOUNCE_BOUNCE_H */
