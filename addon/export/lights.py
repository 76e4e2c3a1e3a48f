"""Blender lights -> BounceLight in radiometric units, matching Cycles (see DESIGN.md, "Light units").

  point, spot  intensity I = colour * P / (4 pi)        (W/sr); 4.5+ without `normalize`: I = colour * P r^2
  spot         half angle = spot_size / 2, blend; Blender < 4.0 also multiplies by cos(phi)
  sun          irradiance E = colour * strength           (W/m^2), angle = angular diameter
  area         radiance L = colour * P / (4 A) before 4.0, colour * P / (pi A) from 4.0 (A with object scale,
               A = pi/4 w h for disk/ellipse); 4.5+ without `normalize`: L = colour * P / pi
  4.5+         colour *= blackbody(temperature) when use_temperature; P = energy * 2^exposure
The area-light and unnormalized figures were measured against Cycles: 3.4.1 gives L A / P = 0.249, 4.3.2 and
5.2.2 give 0.317 (1/pi), and 5.2.2 without `normalize` gives L / P = 0.317.
"""
import math

import bpy

from .. import native

_AREA_TYPES = {"SQUARE": native.LIGHT_AREA_RECT, "RECTANGLE": native.LIGHT_AREA_RECT,
               "DISK": native.LIGHT_AREA_ELLIPSE, "ELLIPSE": native.LIGHT_AREA_ELLIPSE}


def convert_light(light, matrix_world, reports):
    """A native.Light for an evaluated Light datablock placed by `matrix_world`; None for unknown types."""
    out = native.Light()
    out.cast_shadow = 1 if casts_shadow(light) else 0

    position = matrix_world.to_translation()
    basis = matrix_world.to_3x3()
    scale = [basis.col[i].length for i in range(3)]
    axes = [_unit(basis.col[i]) for i in range(3)]
    out.position[:] = tuple(position)
    out.axis_x[:], out.axis_y[:], out.axis_z[:] = axes

    color = _color(light, reports)
    power = float(light.energy) * 2.0 ** float(getattr(light, "exposure", 0.0))
    normalized = bool(getattr(light, "normalize", True))

    if light.type in {"POINT", "SPOT"}:
        out.type = native.LIGHT_POINT if light.type == "POINT" else native.LIGHT_SPOT
        radius = float(light.shadow_soft_size)
        out.radius = radius
        # Unnormalized point radiance is P/pi over a disk of area pi r^2, i.e. I = P r^2.
        intensity = power * radius * radius if (not normalized and radius > 0.0) else power / (4.0 * math.pi)
        _set_intensity(out, color, intensity)
        if light.type == "SPOT":
            out.spot_half_angle = float(light.spot_size) * 0.5
            out.spot_blend = float(light.spot_blend)
            out.spot_cos_falloff = 1 if bpy.app.version < (4, 0, 0) else 0
    elif light.type == "SUN":
        out.type = native.LIGHT_SUN
        out.sun_angle = float(light.angle)
        _set_intensity(out, color, power)
    elif light.type == "AREA":
        shape = light.shape
        out.type = _AREA_TYPES.get(shape, native.LIGHT_AREA_RECT)
        width = float(light.size) * scale[0]
        height = float(light.size_y if shape in {"RECTANGLE", "ELLIPSE"} else light.size) * scale[1]
        out.half_size[:] = (width * 0.5, height * 0.5)
        area = width * height * (math.pi / 4.0 if out.type == native.LIGHT_AREA_ELLIPSE else 1.0)
        if area <= 0.0:
            reports.warn(f"Area light '{light.name}' has zero size and is skipped")
            return None
        _set_intensity(out, color, power * area_radiance_per_watt(area if normalized else 1.0))
    else:
        reports.warn(f"Light '{light.name}' of type {light.type} is not supported")
        return None
    return out


def area_radiance_per_watt(area):
    """Radiance of an area light of `area` m^2 per watt of power, as Cycles of this Blender version emits it."""
    return 1.0 / ((4.0 if bpy.app.version < (4, 0, 0) else math.pi) * area)


def shadow_property(light):
    """(owner, property name) of a light's cast-shadow switch: `use_shadow` from 4.0; on 3.x the Cycles setting
    (3.x's own `use_shadow` is EEVEE's). (None, None) when 3.x runs without the Cycles add-on."""
    if bpy.app.version >= (4, 0, 0):
        return light, "use_shadow"
    cycles = getattr(light, "cycles", None)
    return (cycles, "cast_shadow") if cycles is not None else (None, None)


def casts_shadow(light):
    owner, name = shadow_property(light)
    return bool(getattr(owner, name, True)) if owner is not None else True


def _color(light, reports):
    color = [float(c) for c in light.color]
    if getattr(light, "use_temperature", False):
        temperature_color = getattr(light, "temperature_color", None)
        if temperature_color is None:
            reports.warn(f"Light '{light.name}': colour temperature is not available in this Blender; ignored")
        else:
            color = [c * float(t) for c, t in zip(color, temperature_color)]
    return color


def _set_intensity(out, color, scalar):
    # Non-finite values are passed on: the core skips and counts such lights.
    out.intensity[:] = tuple(c * scalar for c in color)


def _unit(vector):
    length = vector.length
    return tuple(vector / length) if length > 0.0 else (0.0, 0.0, 0.0)
