// Blender's equirectangular mapping of a unit direction e (z up) to uv in [0,1]^2: Cycles'
// direction_to_equirectangular, u = 0.5 - atan2(e.y, e.x) / 2 pi (+x at the image's centre, +y at a quarter). One
// text for the camera's view of the world (shaders/compose/compose.frag) and the world's lights
// (native/src/scene_lights.cpp includes it into C++ with GLM): a copy of it once turned every HDRI by 180 degrees.
// EQUIRECT_INLINE is `inline` in C++.
#ifndef EQUIRECT_INLINE
#define EQUIRECT_INLINE
#endif

const float EQUIRECT_PI = 3.14159265358979f;

EQUIRECT_INLINE vec2 equirect_uv(vec3 e) {
  return vec2(0.5f - atan(e.y, e.x) / (2.0f * EQUIRECT_PI), atan(e.z, length(vec2(e.x, e.y))) / EQUIRECT_PI + 0.5f);
}
