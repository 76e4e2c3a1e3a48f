"""Closed-form irradiance of Blender's lights, in Cycles' units (see DESIGN.md, "Light units").

All functions take receiver points `pts` (N x 3) on a surface of normal `normal` and return irradiance E (N,)
for a white light; a Lambertian surface of albedo a then has radiance a / pi * E.
`matrix` is the light object's 4x4 matrix_world (rows), as Blender reports it.
"""
import math

import numpy as np

UP = np.array([0.0, 0.0, 1.0])


def _frame(matrix):
    m = np.asarray(matrix, dtype=np.float64)
    return m[:3, 3], m[:3, 0], m[:3, 1], m[:3, 2]


def smoothstep(x):
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def point(power, matrix, radius, pts, normal=UP):
    """Point light of radius r: I = P/(4 pi), E = I cos(theta) / (d^2 + r^2)."""
    pos = _frame(matrix)[0]
    d = pos[None, :] - pts
    d2 = np.sum(d * d, axis=1)
    cos = np.clip(d @ normal / np.sqrt(d2), 0.0, None)
    return power / (4.0 * math.pi) * cos / (d2 + radius * radius)


def spot(power, matrix, size, blend, radius, pts, cos_falloff, normal=UP):
    """Spot: point light times smoothstep((cos phi - cos(size/2)) / ((1 - cos(size/2)) blend)), and times
    cos phi too when cos_falloff (Blender 3.x)."""
    pos, _, _, z = _frame(matrix)
    axis = -z / np.linalg.norm(z)
    d = pts - pos[None, :]
    dist = np.linalg.norm(d, axis=1)
    cos_phi = d @ axis / dist
    cos_half = math.cos(size / 2.0)
    spread = (1.0 - cos_half) * blend
    if spread > 0.0:
        att = smoothstep((cos_phi - cos_half) / spread)
    else:
        att = (cos_phi > cos_half).astype(np.float64)
    if cos_falloff:
        att = att * np.clip(cos_phi, 0.0, None)
    return point(power, matrix, radius, pts, normal) * att


def sun(strength, matrix, pts, normal=UP):
    """Sun: E = S cos(theta); the light shines along its -Z axis."""
    z = _frame(matrix)[3]
    to_sun = z / np.linalg.norm(z)
    return np.full(len(pts), strength * max(0.0, float(to_sun @ normal)))


def area_polygon(shape, size, size_y, matrix, segments=1024):
    """World-space corners of an area light (rectangle/square exactly; disk/ellipse as an inscribed polygon
    of `segments` sides) and its world-space area A (object scale applied; pi/4 w h for disk/ellipse)."""
    pos, x, y, _ = _frame(matrix)
    w = size
    h = size_y if shape in ("RECTANGLE", "ELLIPSE") else size
    if shape in ("SQUARE", "RECTANGLE"):
        local = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=np.float64) * 0.5
        area_factor = 1.0
    else:
        phi = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
        local = np.stack([np.cos(phi), np.sin(phi)], axis=1) * 0.5
        area_factor = math.pi / 4.0
    corners = pos[None, :] + (local[:, :1] * w) * x[None, :] + (local[:, 1:] * h) * y[None, :]
    area = area_factor * w * np.linalg.norm(x) * h * np.linalg.norm(y) * _sin_between(x, y)
    return corners, area


def _sin_between(a, b):
    c = np.cross(a, b)
    return float(np.linalg.norm(c) / (np.linalg.norm(a) * np.linalg.norm(b)))


def clip_polygon(corners, plane_point, plane_normal):
    """The part of a convex polygon on the side of plane_normal (Sutherland-Hodgman against one plane)."""
    out = []
    k = len(corners)
    dist = (corners - plane_point[None, :]) @ plane_normal
    for i in range(k):
        a, b, da, db = corners[i], corners[(i + 1) % k], dist[i], dist[(i + 1) % k]
        if da >= 0.0:
            out.append(a)
        if (da >= 0.0) != (db >= 0.0):
            out.append(a + (b - a) * (da / (da - db)))
    return np.array(out).reshape(-1, 3)


def polygon_irradiance(corners, radiance, emit_dir, center, pts, normal=UP):
    """Lambert's formula: irradiance at pts from a planar polygon of uniform Lambertian radiance that emits
    towards the half-space of `emit_dir` (points behind it get 0). All receivers lie on one plane through
    pts[0] with `normal`: the polygon is clipped to the part above it (horizon)."""
    corners = clip_polygon(corners, pts[0], normal)
    if len(corners) < 3:
        return np.zeros(len(pts))
    v = corners[None, :, :] - pts[:, None, :]
    v /= np.linalg.norm(v, axis=2, keepdims=True)
    v1 = np.roll(v, -1, axis=1)
    cross = np.cross(v, v1)
    cross_len = np.linalg.norm(cross, axis=2)
    theta = np.arctan2(cross_len, np.sum(v * v1, axis=2))
    proj = (cross @ normal) / np.maximum(cross_len, 1e-300)
    e = 0.5 * np.abs(np.sum(theta * proj, axis=1)) * radiance
    in_front = (pts - center[None, :]) @ emit_dir > 0.0
    return np.where(in_front, e, 0.0)


def area(power, shape, size, size_y, matrix, pts, normal=UP, segments=1024):
    """Area light: Lambertian radiance P / (4 A) on its -Z side; E by Lambert's formula."""
    corners, a = area_polygon(shape, size, size_y, matrix, segments)
    pos, _, _, z = _frame(matrix)
    return polygon_irradiance(corners, power / (4.0 * a), -z / np.linalg.norm(z), pos, pts, normal)


def area_brute_force(power, shape, size, size_y, matrix, pts, n=400, normal=UP):
    """The same irradiance by midpoint quadrature over the light's surface (for checking `area`)."""
    pos, x, y, z = _frame(matrix)
    w = size
    h = size_y if shape in ("RECTANGLE", "ELLIPSE") else size
    if shape in ("SQUARE", "RECTANGLE"):
        s = (np.arange(n) + 0.5) / n - 0.5
        u, v = np.meshgrid(s, s, indexing="ij")
        u, v = u.ravel(), v.ravel()
        jac = np.full(u.shape, w * h / (n * n))
        a_param = w * h
    else:
        r = (np.arange(n) + 0.5) / n
        phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2.0 * math.pi
        rr, pp = np.meshgrid(r, phi, indexing="ij")
        u, v = (0.5 * rr * np.cos(pp)).ravel(), (0.5 * rr * np.sin(pp)).ravel()
        # dA = (w/2)(h/2) r dr dphi
        jac = (0.25 * w * h * rr * (1.0 / n) * (2.0 * math.pi / (2 * n))).ravel()
        a_param = math.pi / 4.0 * w * h
    scale = np.linalg.norm(x) * np.linalg.norm(y) * _sin_between(x, y)
    area_world = a_param * scale
    radiance = power / (4.0 * area_world)
    samples = pos[None, :] + (u * w)[:, None] * x[None, :] + (v * h)[:, None] * y[None, :]
    emit = -z / np.linalg.norm(z)
    out = np.empty(len(pts))
    for i, p in enumerate(pts):
        d = samples - p[None, :]
        d2 = np.sum(d * d, axis=1)
        dn = d / np.sqrt(d2)[:, None]
        cos_r = np.clip(dn @ normal, 0.0, None)
        cos_l = np.clip(-(dn @ emit), 0.0, None)
        out[i] = radiance * np.sum(cos_r * cos_l / d2 * jac * scale)
    return out


def ortho_pixel_centres(resolution, ortho_scale, center, z=0.0):
    """World positions (rows top first, H x W x 3) of the pixel centres of an orthographic camera looking
    straight down (-Z, +Y up in the image) onto the plane at height z."""
    n = resolution
    s = (np.arange(n) + 0.5) / n - 0.5
    xs = center[0] + s * ortho_scale
    ys = center[1] - s * ortho_scale  # row 0 is the top of the image: largest y
    xx, yy = np.meshgrid(xs, ys)
    return np.stack([xx, yy, np.full_like(xx, z)], axis=-1)


def matrix_world(location, rotation_deg=(0.0, 0.0, 0.0), scale=(1.0, 1.0, 1.0)):
    """Blender's object matrix T @ R @ S for an 'XYZ' Euler rotation (R = Rz Ry Rx), as a 4x4 array."""
    ax, ay, az = (math.radians(a) for a in rotation_deg)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    m = np.eye(4)
    m[:3, :3] = rz @ ry @ rx @ np.diag(scale)
    m[:3, 3] = location
    return m
