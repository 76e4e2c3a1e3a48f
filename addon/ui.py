"""Bounce's panels in the Render properties, and Blender's own light/material/world panels enabled for Bounce."""
import bpy

from . import final, native, presets
from .engine import BounceRenderEngine
from .export.lights import shadow_property
from .properties import VIEWPORT_PREFIX, has_viewport_variant, settings_table

ENGINE_ID = BounceRenderEngine.bl_idname

# Blender panels made visible for Bounce, besides every panel that lists the generic 'BLENDER_RENDER' (output,
# colour management, camera, object data, ...). EEVEE's are used rather than Cycles': they are part of Blender
# itself, and every Cycles panel polls the one COMPAT_ENGINES set of its mixin, so one cannot be shown alone.
# Names missing in a Blender version are skipped.
_BORROWED_PANELS = (
    "DATA_PT_EEVEE_light", "DATA_PT_spot", "DATA_PT_preview",                              # light
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface", "MATERIAL_PT_preview",  # material
    "EEVEE_WORLD_PT_surface",                                                              # world
)
# Generic panels left out: features Bounce does not render, and the light panel that shows the type only (the
# borrowed light panel shows it too).
_EXCLUDED_PANEL_WORDS = ("freestyle", "lightprobe", "falloff_curve")
_EXCLUDED_PANELS = {"DATA_PT_light", "DATA_PT_area", "NODE_DATA_PT_light"}


def _borrowed_panels():
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        name = panel.__name__
        if isinstance(engines, set) and "BLENDER_RENDER" in engines and name not in _EXCLUDED_PANELS \
                and not any(word in name.lower() for word in _EXCLUDED_PANEL_WORDS):
            panels.append(panel)
    for name in _BORROWED_PANELS:
        panel = getattr(bpy.types, name, None)
        if panel is not None and isinstance(getattr(panel, "COMPAT_ENGINES", None), set):
            panels.append(panel)
    return panels


class BouncePanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class BOUNCE_PT_load_error(BouncePanel, bpy.types.Panel):
    bl_label = "Bounce"
    bl_options = {"HIDE_HEADER"}

    @classmethod
    def poll(cls, context):
        return super().poll(context) and native.load_error() is not None

    def draw(self, context):
        box = self.layout.box()
        box.alert = True
        box.label(text="Bounce cannot render: the native library did not load.", icon="ERROR")
        for line in _wrap(native.load_error(), 70):
            box.label(text=line)


class BOUNCE_PT_light_shadow(BouncePanel, bpy.types.Panel):
    bl_label = "Shadow"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.light is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        owner, name = shadow_property(context.light)
        if owner is not None:
            layout.prop(owner, name, text="Cast Shadow")


class BOUNCE_PT_world_visibility(BouncePanel, bpy.types.Panel):
    bl_label = "Visibility"
    bl_context = "world"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.world is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        # Cycles' flag, read by Bounce's export; absent when the Cycles add-on is disabled.
        visibility = getattr(context.world, "cycles_visibility", None)
        if visibility is not None:
            layout.prop(visibility, "camera", text="Camera")
        layout.prop(context.scene.render, "film_transparent", text="Film Transparent")


class BOUNCE_PT_last_render(BouncePanel, bpy.types.Panel):
    bl_label = "Last Render"
    bl_options = {"DEFAULT_CLOSED"}
    bl_order = 100

    def draw(self, context):
        layout = self.layout
        info = final.last_render
        if not info:
            layout.label(text="No final render yet")
            return
        col = layout.column(align=True)
        col.label(text=f"{info['width']} x {info['height']}, {info['samples']} samples, "
                       f"render {info['render_seconds'] * 1e3:.0f} ms, sync {info['sync_seconds'] * 1e3:.0f} ms")
        col.label(text=f"{info['triangles']:,} triangles, {info['instances']} instances, {info['meshes']} meshes, "
                       f"{info['lights']} lights, {info['gpu_bytes'] / 2**20:.1f} MiB")
        for line in _wrap(info["plan"], 70):
            col.label(text=line)
        if info["indirect"]:
            col.label(text=info["indirect"])
        if info.get("topology"):
            col.label(text=f"Topology {info['topology']}")
        if info["dropped_triangles"] or info["skipped_lights"]:
            col.label(text=f"Dropped {info['dropped_triangles']:,} triangles, skipped {info['skipped_lights']} "
                           "lights", icon="ERROR")
        if info.get("error"):
            # What accuracy costs: the estimated error now and for more samples (its measure is the benchmarks').
            layout.label(text="Error (estimated relMSE) for more samples", icon="TIME")
            if info["bias_relmse"] >= 0.0:
                layout.label(text=f"Of it {info['bias_relmse']:.2g} is what the render leaves out or its method's "
                                  "bias: more samples keep it")
            grid = layout.grid_flow(row_major=True, columns=3, even_columns=True, align=True)
            for label in ("Samples", "Time", "relMSE"):
                grid.label(text=label)
            for samples, seconds, relmse in info["error"]:
                grid.label(text=f"{samples}")
                grid.label(text=f"{seconds:.3g} s")
                grid.label(text=f"{relmse:.2g}")
        if info["stages"]:
            grid = layout.grid_flow(row_major=True, columns=3, even_columns=True, align=True)
            for label in ("Stage", "GPU ms", "CPU ms"):
                grid.label(text=label)
            for name, gpu_ms, cpu_ms in info["stages"]:
                grid.label(text=name)
                grid.label(text=f"{gpu_ms:.2f}")
                grid.label(text=f"{cpu_ms:.2f}")


# Lines shown at the top of a settings group's panel.
GROUP_NOTES = {
    "Screen-Space VPL Propagation":
        "Every light bounces: each sample draws Bouncing Lights of them by the light they bring into the scene, "
        "so with many lights (a world's directions, emissive surfaces) the bounce needs more samples to lose its "
        "noise.",
    "Topology":
        "Renders on the CPU. The first render of a scene precomputes the topology of its empty space (cached by "
        "geometry and grid settings: moving the camera or a light reuses it). Rays pass through alpha cut-outs; "
        "the topology counts them as walls. Forward Light Cuts' Indirect Shadows use this grid too.",
}


# Methods each setting applies to, where not every method reads it: the row is greyed out for the others.
ROW_METHODS = {"bounces": {"SSVP", "TOPOLOGY"}, "auto_threshold": {"AUTO"}, "sample_budget": {"AUTO"}}
# Settings whose value a method caps below the property's maximum: (method, cap, note).
ROW_CAPS = {"bounces": ("SSVP", 2, "Screen-Space VPL Propagation simulates 2 bounces at most")}


def _draw_row(layout, props, row):
    name = row["name"]
    methods = ROW_METHODS.get(name)
    column = layout.column()
    column.active = methods is None or props.method in methods
    if has_viewport_variant(row):
        labels, values = _label_split(column)
        labels.label(text=row["label"])
        values.prop(props, name, text="")
        values.prop(props, VIEWPORT_PREFIX + name, text="")
    else:
        column.prop(props, name)
    method, cap, note = ROW_CAPS.get(name, (None, None, None))
    if props.method == method and getattr(props, name) > cap:
        column.label(text=note, icon="INFO")


def _settings_panel(group, rows, order):
    """A Render-properties panel for one `group` of the settings table; viewport variants sit beside."""
    has_pairs = any(has_viewport_variant(row) for row in rows)

    def draw(self, context):
        props = context.scene.bounce
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        presets.draw_buttons(layout, group)
        note = GROUP_NOTES.get(group)
        if note:
            col = layout.column(align=True)
            for line in _wrap(note, 60):
                col.label(text=line)
        if has_pairs:
            _labels, values = _label_split(layout)
            values.label(text="Render")
            values.label(text="Viewport")
        for row in rows:
            _draw_row(layout, props, row)
        extra = GROUP_EXTRAS.get(group)
        if extra is not None:
            extra(layout, props, context)

    slug = "".join(c if c.isalnum() else "_" for c in group.lower())
    return type(f"BOUNCE_PT_settings_{slug}", (BouncePanel, bpy.types.Panel),
                {"bl_label": group, "bl_order": order, "draw": draw})


BAR_WIDTH = 10  # characters of a full share bar
BAR_GLYPH = "\u2588"


def _chars_fitting(context):
    """About how many characters of Blender's interface font fit across the region."""
    return max(20, int(context.region.width / (9.0 * context.preferences.view.ui_scale)))


def _draw_auto_plan(layout, props, context):
    """What Auto chose the last time it rendered, in words, and each component's share of the image as a bar."""
    if props.method != "AUTO":
        return
    box = layout.box()
    plan = final.last_plan
    if not plan:
        box.label(text="Auto's plan shows here after a render", icon="INFO")
        return
    col = box.column(align=True)
    col.label(text=plan["method"], icon="LIGHT")
    col.label(text=f"(last {plan['where']})")
    col = box.column(align=True)
    for line in _wrap(plan["text"], _chars_fitting(context)):
        col.label(text=line)
    col = box.column(align=True)
    for label, share in plan["components"]:
        bar = BAR_GLYPH * max(1, round(BAR_WIDTH * share))
        col.label(text=f"{bar} {100 * share:.1f} % {label}")


# Drawn below a group's settings.
GROUP_EXTRAS = {"General": _draw_auto_plan}


def _label_split(layout):
    """A row laid out like use_property_split: a right-aligned label column, then an aligned row of values."""
    split = layout.split(factor=0.4)
    labels = split.row()
    labels.alignment = "RIGHT"
    return labels, split.row(align=True)


def _wrap(text, width):
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return lines + ([line] if line else [])


class _Registered:
    panels = []      # classes registered here
    borrowed = []    # Blender panels whose COMPAT_ENGINES got ENGINE_ID
    copied = []      # those of them that got a COMPAT_ENGINES set of their own


def _add_engine(panel):
    # A panel that inherits COMPAT_ENGINES from a mixin shares the set with its siblings; adding to it would show
    # all of them. Such a panel gets a set of its own, removed again on unregister.
    if "COMPAT_ENGINES" not in panel.__dict__:
        panel.COMPAT_ENGINES = set(panel.COMPAT_ENGINES)
        _Registered.copied.append(panel)
    panel.COMPAT_ENGINES.add(ENGINE_ID)
    _Registered.borrowed.append(panel)


def _settings_panels():
    groups = {}
    for row in settings_table():
        groups.setdefault(row["group"], []).append(row)
    return [_settings_panel(group, rows, order) for order, (group, rows) in enumerate(groups.items(), start=1)]


def register():
    _Registered.panels = [BOUNCE_PT_load_error, *_settings_panels(), BOUNCE_PT_last_render, BOUNCE_PT_light_shadow,
                          BOUNCE_PT_world_visibility]
    for panel in _Registered.panels:
        bpy.utils.register_class(panel)
    for panel in _borrowed_panels():
        if ENGINE_ID not in panel.COMPAT_ENGINES:
            _add_engine(panel)


def unregister():
    for panel in _Registered.borrowed:
        if panel in _Registered.copied:
            del panel.COMPAT_ENGINES
        else:
            panel.COMPAT_ENGINES.discard(ENGINE_ID)
    _Registered.borrowed, _Registered.copied = [], []
    for panel in reversed(_Registered.panels):
        bpy.utils.unregister_class(panel)
    _Registered.panels = []
