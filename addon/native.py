"""The one ctypes binding of libbounce (native/include/bounce/bounce.h).

Everything that touches ctypes lives here: loading the library, the signature of every function, the struct
mirrors (same field order and types as bounce.h), and the status-code -> exception choke point. The rest of the
add-on talks to `Engine` and passes numpy arrays.

Ownership: the C API copies every array before a call returns, so the numpy arrays only need to live for the
duration of the call.
"""
import ctypes
import json
import os

import numpy as np

API_VERSION = 13  # BOUNCE_API_VERSION this module was written against

LIBRARY_ENV = "BOUNCE_LIBRARY"
LIBRARY_NAME = "libbounce.so"

# ---- Errors ---------------------------------------------------------------------------------------------


class BounceError(Exception):
    """A failed libbounce call; `status` is the BounceStatus, the message is bounce_last_error()."""

    status = None

    def __init__(self, message, status=None):
        super().__init__(message)
        if status is not None:
            self.status = status


class LibraryLoadError(BounceError):
    """libbounce could not be loaded, or is of another API version."""


class InvalidArgumentError(BounceError):
    status = 1


class ContextError(BounceError):
    status = 2


class GLError(BounceError):
    status = 3


class OutOfMemoryError(BounceError):
    status = 4


class NotReadyError(BounceError):
    status = 5


class CancelledError(BounceError):
    status = 6


class InternalError(BounceError):
    status = 7


class RayTracingError(BounceError):
    status = 8


_ERROR_BY_STATUS = {cls.status: cls for cls in (InvalidArgumentError, ContextError, GLError, OutOfMemoryError,
                                                NotReadyError, CancelledError, InternalError, RayTracingError)}

# ---- Enums and constants (bounce.h) ----------------------------------------------------------------------

SETTING_VIEWPORT = 1
SETTING_PIXEL = 2
SETTING_FACTOR = 4
SETTING_ANGLE = 8

TEXTURE_RGBA8_SRGB = 0
TEXTURE_RGBA8_LINEAR = 1
TEXTURE_RGBA32F = 2
NO_TEXTURE = 0

LIGHT_POINT = 0
LIGHT_SPOT = 1
LIGHT_SUN = 2
LIGHT_AREA_RECT = 3
LIGHT_AREA_ELLIPSE = 4

METHOD_AUTO = 0
METHOD_DIRECT = 1
METHOD_FLC = 2
METHOD_SSVP = 3
METHOD_TOPOLOGY = 4
METHOD_NAMES = ("Auto", "Direct", "Forward Light Cuts", "Screen-Space VPL Propagation", "Topology")

AOV_COMBINED = 0
AOV_DIRECT = 1
AOV_EMISSION = 2
AOV_ALBEDO = 3
AOV_NORMAL = 4
AOV_DEPTH = 5
AOV_INDIRECT = 6
AOV_VPLS = 7
AOV_SECOND_BOUNCE = 8
AOV_TOPOLOGY = 9
AOV_COUNT = 10

RENDER_IDLE = 0
RENDER_RUNNING = 1
RENDER_DONE = 2
RENDER_FAILED = 3
RENDER_CANCELLED = 4

MAX_STAGES = 16
TOPOLOGY_STAGES = 6

# ---- Struct mirrors (field order and types exactly as in bounce.h) --------------------------------------

_f32 = ctypes.c_float
_i32 = ctypes.c_int32
_u32 = ctypes.c_uint32
_u64 = ctypes.c_uint64


class EngineDesc(ctypes.Structure):
    _fields_ = [("egl_platform", ctypes.c_char_p),
                ("debug_gl", _i32)]


class MeshDesc(ctypes.Structure):
    _fields_ = [("vertex_count", _u32),
                ("positions", ctypes.POINTER(_f32)),
                ("triangle_count", _u32),
                ("triangles", ctypes.POINTER(_u32)),
                ("corner_normals", ctypes.POINTER(_f32)),
                ("corner_uvs", ctypes.POINTER(_f32)),
                ("triangle_slots", ctypes.POINTER(_i32))]


class Material(ctypes.Structure):
    _fields_ = [("base_color", _f32 * 3),
                ("alpha", _f32),
                ("base_color_texture", _u64),
                ("alpha_from_texture", _i32),
                ("alpha_threshold", _f32),
                ("emission", _f32 * 3),
                ("double_sided", _i32),
                ("emission_texture", _u64)]


class InstancesDesc(ctypes.Structure):
    _fields_ = [("count", _u32),
                ("mesh_keys", ctypes.POINTER(_u64)),
                ("matrices", ctypes.POINTER(_f32)),
                ("slot_offsets", ctypes.POINTER(_u32)),
                ("slot_counts", ctypes.POINTER(_u32)),
                ("slot_material_count", _u32),
                ("slot_materials", ctypes.POINTER(_u32))]


class Light(ctypes.Structure):
    _fields_ = [("type", _i32),
                ("cast_shadow", _i32),
                ("position", _f32 * 3),
                ("axis_x", _f32 * 3),
                ("axis_y", _f32 * 3),
                ("axis_z", _f32 * 3),
                ("intensity", _f32 * 3),
                ("radius", _f32),
                ("half_size", _f32 * 2),
                ("spot_half_angle", _f32),
                ("spot_blend", _f32),
                ("spot_cos_falloff", _i32),
                ("sun_angle", _f32),
                ("triangle", _f32 * 4)]


class World(ctypes.Structure):
    _fields_ = [("background", _f32 * 3),
                ("transparent", _i32),
                ("environment_texture", ctypes.c_uint64),
                ("world_to_environment", _f32 * 9),
                ("camera_hidden", _i32)]


class SceneStats(ctypes.Structure):
    _fields_ = [("mesh_count", _u32),
                ("instance_count", _u32),
                ("triangle_count", _u64),
                ("dropped_triangles", _u64),
                ("light_count", _u32),
                ("skipped_lights", _u32),
                ("texture_count", _u32),
                ("gpu_bytes", _u64),
                ("bounds_min", _f32 * 3),
                ("bounds_max", _f32 * 3),
                ("out_of_range_triangles", _u64),
                ("out_of_range_instances", _u32),
                ("out_of_range_lights", _u32),
                ("clamped_lights", _u32)]


class Camera(ctypes.Structure):
    _fields_ = [("world_to_view", _f32 * 16),
                ("projection", _f32 * 16),
                ("width", _i32),
                ("height", _i32),
                ("crop", _i32 * 4),
                ("frame", _i32)]


class RenderProgress(ctypes.Structure):
    _fields_ = [("state", _i32),
                ("samples_done", _i32),
                ("samples_total", _i32),
                ("progress", _f32),
                ("frame_serial", _u64),
                ("stage", ctypes.c_char * 64)]

    def stage_text(self):
        """What runs before sampling (e.g. "Topology: thinning"), or ""."""
        return self.stage.decode("utf-8", "replace")


class StageTime(ctypes.Structure):
    _fields_ = [("name", ctypes.c_char * 32),
                ("gpu_ms", ctypes.c_double),
                ("cpu_ms", ctypes.c_double)]


class LightShares(ctypes.Structure):
    _fields_ = [("direct", _f32 * 3),
                ("first_bounce", _f32 * 3),
                ("second_bounce", _f32),
                ("emission_seen", _f32),
                ("background_seen", _f32),
                ("mean_albedo", _f32),
                ("openness", _f32),
                ("analysis_ms", _f32)]

    SOURCES = ("Lamps", "World", "Emission")

    def components(self):
        """[(label, share), ...] of the image's components with light, largest first."""
        rows = [(f"{source} direct", self.direct[i]) for i, source in enumerate(self.SOURCES)]
        rows += [(f"{source} first bounce", self.first_bounce[i]) for i, source in enumerate(self.SOURCES)]
        rows += [("Second bounce", self.second_bounce), ("Emission seen", self.emission_seen),
                 ("World seen", self.background_seen)]
        return sorted(((label, share) for label, share in rows if share > 0.0), key=lambda row: -row[1])


class FrameInfo(ctypes.Structure):
    _fields_ = [("width", _i32),
                ("height", _i32),
                ("samples", _i32),
                ("serial", _u64),
                ("stage_count", _i32),
                ("stages", StageTime * MAX_STAGES),
                ("nonfinite_pixels", _u64),
                ("vpl_count", _u64),
                ("divergent_triangles", _u64),
                ("main_light", _i32),
                ("cluster_count", _i32),
                ("method", _i32),
                ("bounces", _i32),
                ("plan_text", ctypes.c_char * 512),
                ("shares", LightShares),
                ("noise_relmse", _f32), ("noise_direct_relmse", _f32), ("noise_direct_rate", _f32),
                ("bias_relmse", _f32),
                ("aovs", _u32)]

    def plan(self):
        """Auto's plan in a few sentences; "" for an explicit method."""
        return self.plan_text.decode("utf-8", "replace")

    def stage_list(self):
        """[(name, gpu_ms, cpu_ms), ...] of the stages filled in."""
        count = max(0, min(self.stage_count, MAX_STAGES))
        return [(s.name.decode("utf-8", "replace"), s.gpu_ms, s.cpu_ms) for s in self.stages[:count]]


class TopologyInfo(ctypes.Structure):
    _fields_ = [("available", _i32),
                ("grid", _i32 * 3),
                ("voxel_size", _f32),
                ("skeleton_nodes", _u32),
                ("segmented_nodes", _u32),
                ("clusters", _u32),
                ("gates", _u32),
                ("builds", _u64),
                ("stage_names", (ctypes.c_char * 24) * TOPOLOGY_STAGES),
                ("stage_ms", ctypes.c_double * TOPOLOGY_STAGES)]

    def stage_list(self):
        """[(name, ms), ...] of the precomputation's stages."""
        return [(bytes(self.stage_names[i]).split(b"\0")[0].decode(), self.stage_ms[i])
                for i in range(TOPOLOGY_STAGES)]

    def summary(self):
        """One line: the grid, the counts and the time of each stage."""
        stages = ", ".join(f"{name} {ms / 1000:.2f} s" for name, ms in self.stage_list())
        return (f"grid {self.grid[0]}x{self.grid[1]}x{self.grid[2]}, {self.skeleton_nodes} skeleton nodes, "
                f"{self.clusters} visibility clusters, {self.gates} gates | {stages}")


def struct_array(struct_type, items):
    """A ctypes array of `struct_type` filled from a list of instances (for the *_set calls)."""
    array = (struct_type * max(1, len(items)))()
    for i, item in enumerate(items):
        array[i] = item
    return array


# ---- Library --------------------------------------------------------------------------------------------

COST_MODEL_ENV = "BOUNCE_COST_MODEL_DIR"


def cost_model_directory():
    """Where Auto's cost model of this machine is kept between Blender sessions (bounce_cost_model_directory):
    $BOUNCE_COST_MODEL_DIR ("off" or empty: not kept), else bounce/ in the user's cache ($XDG_CACHE_HOME or
    ~/.cache)."""
    chosen = os.environ.get(COST_MODEL_ENV)
    if chosen is not None:
        return "" if chosen in ("", "off") else chosen
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "bounce")

_Engine_p = ctypes.c_void_p  # BounceEngine*: opaque


class Library:
    """libbounce loaded at an absolute path, with every signature declared and the settings struct built."""

    def __init__(self, path):
        self.path = path
        self.cdll = ctypes.CDLL(path)
        self._declare()
        self.version = self.cdll.bounce_version().decode()
        api = self.cdll.bounce_api_version()
        if api != API_VERSION:
            raise LibraryLoadError(f"{path} has C API version {api}, this add-on needs version {API_VERSION}: "
                                   "rebuild the library and the add-on from the same checkout")
        self.settings_table = json.loads(self.cdll.bounce_settings_table_json().decode())
        self.Settings = _settings_struct(self.settings_table)
        native_size = self.cdll.bounce_settings_size()
        if ctypes.sizeof(self.Settings) != native_size:
            raise LibraryLoadError(f"settings table of {path} describes {ctypes.sizeof(self.Settings)} bytes "
                                   f"but bounce_settings_size() is {native_size}")
        self.cdll.bounce_cost_model_directory(cost_model_directory().encode())

    def last_error(self):
        return (self.cdll.bounce_last_error() or b"").decode("utf-8", "replace")

    def _errcheck(self, status, func, _args):
        if status == 0:
            return status
        message = self.last_error() or f"{func.__name__} failed with status {status}"
        raise _ERROR_BY_STATUS.get(status, BounceError)(message, status)

    def _declare(self):
        c = self.cdll
        size_t = ctypes.c_size_t
        status_functions = {
            "bounce_settings_validate": [ctypes.c_void_p],
            "bounce_engine_create": [ctypes.POINTER(EngineDesc), ctypes.POINTER(_Engine_p)],
            "bounce_engine_gl_info": [_Engine_p, ctypes.c_char_p, size_t],
            "bounce_mesh_set": [_Engine_p, _u64, ctypes.POINTER(MeshDesc)],
            "bounce_mesh_remove": [_Engine_p, _u64],
            "bounce_texture_set": [_Engine_p, _u64, _i32, _i32, _i32, ctypes.c_void_p],
            "bounce_texture_remove": [_Engine_p, _u64],
            "bounce_materials_set": [_Engine_p, _u32, ctypes.POINTER(Material)],
            "bounce_instances_set": [_Engine_p, ctypes.POINTER(InstancesDesc)],
            "bounce_lights_set": [_Engine_p, _u32, ctypes.POINTER(Light)],
            "bounce_world_set": [_Engine_p, ctypes.POINTER(World)],
            "bounce_scene_stats": [_Engine_p, ctypes.POINTER(SceneStats)],
            "bounce_render_start": [_Engine_p, ctypes.c_void_p, ctypes.POINTER(Camera)],
            "bounce_render_cancel": [_Engine_p],
            "bounce_render_progress": [_Engine_p, ctypes.POINTER(RenderProgress)],
            "bounce_render_wait": [_Engine_p, _i32],
            "bounce_frame_info": [_Engine_p, ctypes.POINTER(FrameInfo)],
            "bounce_frame_read": [_Engine_p, _i32, ctypes.POINTER(_f32), size_t],
            "bounce_topology_info": [_Engine_p, ctypes.POINTER(TopologyInfo)],
            "bounce_cost_model_directory": [ctypes.c_char_p],
        }
        for name, argtypes in status_functions.items():
            func = getattr(c, name)
            func.argtypes = argtypes
            func.restype = ctypes.c_int  # BounceStatus
            func.errcheck = self._errcheck
        other_functions = {
            "bounce_version": ([], ctypes.c_char_p),
            "bounce_api_version": ([], _i32),
            "bounce_last_error": ([], ctypes.c_char_p),
            "bounce_settings_size": ([], size_t),
            "bounce_settings_defaults": ([ctypes.c_void_p], None),
            "bounce_settings_table_json": ([], ctypes.c_char_p),
            "bounce_engine_destroy": ([_Engine_p], None),
            "bounce_aov_channels": ([_i32], _i32),
            "bounce_aov_name": ([_i32], ctypes.c_char_p),
            "bounce_method_aovs": ([_i32], ctypes.c_uint32),
        }
        for name, (argtypes, restype) in other_functions.items():
            func = getattr(c, name)
            func.argtypes = argtypes
            func.restype = restype

    # Library-level calls

    def default_settings(self):
        settings = self.Settings()
        self.cdll.bounce_settings_defaults(ctypes.byref(settings))
        return settings

    def validate_settings(self, settings):
        self.cdll.bounce_settings_validate(ctypes.byref(settings))

    def aov_channels(self, aov):
        return self.cdll.bounce_aov_channels(aov)

    def aov_name(self, aov):
        return (self.cdll.bounce_aov_name(aov) or b"").decode()

    def method_aovs(self, method):
        """The AOVs method `method` (an int) writes, as bits 1 << aov."""
        return self.cdll.bounce_method_aovs(method)


def _settings_struct(table):
    """The ctypes mirror of BounceSettings: one 4-byte member per table row, in table order."""
    fields = [(row["name"], _f32 if row["kind"] == "FLOAT" else _i32) for row in table]
    return type("Settings", (ctypes.Structure,), {"_fields_": fields})


def library_path():
    """Where libbounce is loaded from: $BOUNCE_LIBRARY, else beside this package."""
    return os.environ.get(LIBRARY_ENV) or os.path.join(os.path.dirname(os.path.abspath(__file__)), LIBRARY_NAME)


_library = None
_load_error = None


def library():
    """The loaded Library (loaded once); raises LibraryLoadError with the path tried and how to build it."""
    global _library, _load_error
    if _library is not None:
        return _library
    if _load_error is not None:
        raise _load_error
    path = library_path()
    try:
        if not os.path.isfile(path):
            raise LibraryLoadError(f"Bounce's native library was not found at {path}")
        _library = Library(path)
    except LibraryLoadError as error:
        _load_error = LibraryLoadError(f"{error}. {_BUILD_HINT}")
        raise _load_error from None
    except (OSError, AttributeError) as error:
        # OSError: dlopen failed (missing dependency, wrong architecture); AttributeError: a missing symbol.
        _load_error = LibraryLoadError(f"Bounce's native library at {path} could not be loaded: {error}. "
                                       f"{_BUILD_HINT}")
        raise _load_error from None
    return _library


def load_error():
    """The message of the library-load failure, or None when loaded (tries to load once)."""
    try:
        library()
    except LibraryLoadError as error:
        return str(error)
    return None


_BUILD_HINT = ("Build it with `cmake -S <checkout> -B <checkout>/build -G Ninja && cmake --build <checkout>/build` "
               "and start Blender with scripts/blender, or set BOUNCE_LIBRARY to the library's path")

# ---- Engine ---------------------------------------------------------------------------------------------


def _pointer(array, ctype):
    return array.ctypes.data_as(ctypes.POINTER(ctype)) if array is not None else None


def _contiguous(array, dtype):
    return None if array is None else np.ascontiguousarray(array, dtype=dtype)


class Engine:
    """One native engine (render thread + GL context). A context manager; close() is idempotent."""

    def __init__(self, egl_platform=None, debug_gl=False, lib=None):
        self._handle = None
        self.lib = lib or library()
        self._c = self.lib.cdll
        desc = EngineDesc(egl_platform.encode() if egl_platform else None, 1 if debug_gl else 0)
        handle = _Engine_p()
        self._c.bounce_engine_create(ctypes.byref(desc), ctypes.byref(handle))
        self._handle = handle

    def close(self):
        handle, self._handle = self._handle, None
        if handle:
            self._c.bounce_engine_destroy(handle)

    @property
    def closed(self):
        return not self._handle

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        self.close()

    def _h(self):
        if not self._handle:
            raise InvalidArgumentError("the Bounce engine was already closed", 1)
        return self._handle

    def gl_info(self):
        buffer = ctypes.create_string_buffer(512)
        self._c.bounce_engine_gl_info(self._h(), buffer, len(buffer))
        return buffer.value.decode("utf-8", "replace")

    # Scene

    def set_mesh(self, key, positions, triangles, corner_normals=None, corner_uvs=None, triangle_slots=None):
        """positions (V,3) float32, triangles (T,3) uint32, corner_normals (T,3,3), corner_uvs (T,3,2),
        triangle_slots (T,) int32; any array may be given flat."""
        positions = _contiguous(positions, np.float32)
        triangles = _contiguous(triangles, np.uint32)
        corner_normals = _contiguous(corner_normals, np.float32)
        corner_uvs = _contiguous(corner_uvs, np.float32)
        triangle_slots = _contiguous(triangle_slots, np.int32)
        desc = MeshDesc(positions.size // 3, _pointer(positions, _f32), triangles.size // 3,
                        _pointer(triangles, _u32), _pointer(corner_normals, _f32), _pointer(corner_uvs, _f32),
                        _pointer(triangle_slots, _i32))
        self._c.bounce_mesh_set(self._h(), key, ctypes.byref(desc))

    def remove_mesh(self, key):
        self._c.bounce_mesh_remove(self._h(), key)

    def set_texture(self, key, width, height, texture_format, pixels):
        """pixels: width*height*4 uint8 (RGBA8_*) or float32 (RGBA32F), bottom row first."""
        dtype = np.float32 if texture_format == TEXTURE_RGBA32F else np.uint8
        pixels = np.ascontiguousarray(pixels, dtype=dtype)
        if pixels.size != width * height * 4:
            raise InvalidArgumentError(f"texture {key}: {pixels.size} values for {width}x{height} RGBA", 1)
        self._c.bounce_texture_set(self._h(), key, width, height, texture_format, pixels.ctypes.data)

    def remove_texture(self, key):
        self._c.bounce_texture_remove(self._h(), key)

    def set_materials(self, materials):
        """materials: a list of Material."""
        self._c.bounce_materials_set(self._h(), len(materials), struct_array(Material, materials))

    def set_instances(self, mesh_keys, matrices, slot_offsets, slot_counts, slot_materials):
        """mesh_keys (N,) uint64, matrices (N,16) float32 column-major, slot_offsets/slot_counts (N,) uint32,
        slot_materials (M,) uint32 indices into the material table."""
        mesh_keys = _contiguous(mesh_keys, np.uint64)
        matrices = _contiguous(matrices, np.float32)
        slot_offsets = _contiguous(slot_offsets, np.uint32)
        slot_counts = _contiguous(slot_counts, np.uint32)
        slot_materials = _contiguous(slot_materials, np.uint32)
        desc = InstancesDesc(mesh_keys.size, _pointer(mesh_keys, _u64), _pointer(matrices, _f32),
                             _pointer(slot_offsets, _u32), _pointer(slot_counts, _u32), slot_materials.size,
                             _pointer(slot_materials, _u32))
        self._c.bounce_instances_set(self._h(), ctypes.byref(desc))

    def set_lights(self, lights):
        """lights: a list of Light."""
        self._c.bounce_lights_set(self._h(), len(lights), struct_array(Light, lights))

    def set_world(self, world):
        self._c.bounce_world_set(self._h(), ctypes.byref(world))

    def scene_stats(self):
        stats = SceneStats()
        self._c.bounce_scene_stats(self._h(), ctypes.byref(stats))
        return stats

    # Rendering

    def render_start(self, settings, camera):
        self._c.bounce_render_start(self._h(), ctypes.byref(settings), ctypes.byref(camera))

    def render_cancel(self):
        self._c.bounce_render_cancel(self._h())

    def render_progress(self):
        progress = RenderProgress()
        self._c.bounce_render_progress(self._h(), ctypes.byref(progress))
        return progress

    def topology_info(self):
        """The TopologyInfo of the last TOPOLOGY render (available == 0 before one)."""
        info = TopologyInfo()
        self._c.bounce_topology_info(self._h(), ctypes.byref(info))
        return info

    def render_wait(self, timeout_ms):
        """True when the render ended (done), False on timeout; raises the render's failure or CancelledError."""
        try:
            self._c.bounce_render_wait(self._h(), int(timeout_ms))
        except NotReadyError:
            return False
        return True

    def frame_info(self):
        """The published frame's FrameInfo, or None when nothing is published yet."""
        info = FrameInfo()
        try:
            self._c.bounce_frame_info(self._h(), ctypes.byref(info))
        except NotReadyError:
            return None
        return info

    def frame_read(self, aov, width, height, out=None):
        """One AOV of the frame the last frame_info() described, as a (height*width, channels) float32 array, rows
        bottom first."""
        channels = self.lib.aov_channels(aov)
        if channels <= 0:
            raise InvalidArgumentError(f"unknown AOV {aov}", 1)
        shape = (width * height, channels)
        if out is None or out.shape != shape or out.dtype != np.float32 or not out.flags.c_contiguous:
            out = np.empty(shape, dtype=np.float32)
        self._c.bounce_frame_read(self._h(), aov, _pointer(out, _f32), out.size)
        return out
