"""`scene.bounce`: the render settings, generated from the native settings table.

Every setting is declared once, in native/include/bounce/settings.def; libbounce describes the table as JSON and
this module turns each row into a Blender property (label, tooltip, default, limits, subtype, enum items).
Rows flagged BOUNCE_SETTING_VIEWPORT get a second property with the `viewport_` prefix, used by the viewport.
"""
import bpy

from . import native

VIEWPORT_PREFIX = "viewport_"

_INT_SUBTYPES = {native.SETTING_PIXEL: "PIXEL", native.SETTING_FACTOR: "FACTOR"}
_FLOAT_SUBTYPES = {native.SETTING_PIXEL: "PIXEL", native.SETTING_FACTOR: "FACTOR", native.SETTING_ANGLE: "ANGLE"}


def settings_table():
    """The native settings table (list of dicts), or [] when libbounce is not loaded."""
    try:
        return native.library().settings_table
    except native.LibraryLoadError:
        return []


def has_viewport_variant(row):
    return bool(row["flags"] & native.SETTING_VIEWPORT)


def _subtype(row, subtypes):
    for flag, subtype in subtypes.items():
        if row["flags"] & flag:
            return subtype
    return "NONE"


def _enum_items(row):
    return [(ident, label, tooltip, value) for value, (ident, label, tooltip) in enumerate(row["items"])]


def _property(row, label, description, default_key="default"):
    """A bpy.props definition for one table row, with the default under `default_key` ("viewport_default" for the
    `viewport_` variant)."""
    kind = row["kind"]
    row = dict(row, default=row.get(default_key, row["default"]))
    common = {"name": label, "description": description}
    if kind == "ENUM":
        items = _enum_items(row)
        default = items[int(row["default"])][0] if 0 <= int(row["default"]) < len(items) else items[0][0]
        return bpy.props.EnumProperty(items=items, default=default, **common)
    if kind == "BOOL":
        return bpy.props.BoolProperty(default=bool(row["default"]), **common)
    if kind == "INT":
        return bpy.props.IntProperty(default=int(row["default"]), min=int(row["min"]), max=int(row["max"]),
                                     soft_min=int(row["soft_min"]), soft_max=int(row["soft_max"]),
                                     subtype=_subtype(row, _INT_SUBTYPES), **common)
    if kind == "FLOAT":
        return bpy.props.FloatProperty(default=float(row["default"]), min=float(row["min"]), max=float(row["max"]),
                                       soft_min=float(row["soft_min"]), soft_max=float(row["soft_max"]),
                                       subtype=_subtype(row, _FLOAT_SUBTYPES), **common)
    raise ValueError(f"setting '{row['name']}' has unknown kind '{kind}'")


def _annotations(table):
    annotations = {}
    for row in table:
        annotations[row["name"]] = _property(row, row["label"], row["description"])
        if has_viewport_variant(row):
            annotations[VIEWPORT_PREFIX + row["name"]] = _property(
                row, "Viewport " + row["label"], row["description"] + " (viewport)", "viewport_default")
    return annotations


def fill_settings(props, viewport=False):
    """A native Settings struct from a `scene.bounce` PropertyGroup, for a final render or the viewport (where
    the `viewport_` variant of a setting, if any, goes into the struct member)."""
    lib = native.library()
    settings = lib.default_settings()
    for row in lib.settings_table:
        name = row["name"]
        source = VIEWPORT_PREFIX + name if viewport and has_viewport_variant(row) else name
        value = getattr(props, source, None)
        if value is None:
            continue
        if row["kind"] == "ENUM":
            value = _enum_value(row, value)
        setattr(settings, name, int(value) if row["kind"] != "FLOAT" else float(value))
    lib.validate_settings(settings)
    return settings


def _enum_value(row, identifier):
    """The C value of an enum setting's item; 0 (its first item) for an unknown one, e.g. a raw ID property."""
    return next((v for v, (ident, _label, _tip) in enumerate(row["items"]) if ident == identifier), 0)


def method_of(props):
    """The C value of `props.method`, as fill_settings sends it (without validating the other settings)."""
    row = next(row for row in native.library().settings_table if row["name"] == "method")
    return _enum_value(row, props.method)


class _Registered:
    settings_class = None


def register():
    # Without libbounce the group is empty; the render panel then explains why (see ui.py).
    table = settings_table()
    cls = type("BounceSceneSettings", (bpy.types.PropertyGroup,), {"__annotations__": _annotations(table),
                                                                    "__doc__": "Bounce render settings"})
    bpy.utils.register_class(cls)
    _Registered.settings_class = cls
    bpy.types.Scene.bounce = bpy.props.PointerProperty(type=cls, name="Bounce", description="Bounce render settings")


def unregister():
    if hasattr(bpy.types.Scene, "bounce"):
        del bpy.types.Scene.bounce
    if _Registered.settings_class is not None:
        bpy.utils.unregister_class(_Registered.settings_class)
        _Registered.settings_class = None
