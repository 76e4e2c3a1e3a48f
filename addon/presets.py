"""Quality presets of the settings panels: named sets of scene.bounce values, applied by an operator."""
import bpy

# Forward Light Cuts: N_avg and tiling trade time for noise (paper Fig. 9, 10); the blur hides what noise the
# interleaving leaves; samples average independent frames (Sec. 6). Viewport values refine while idle.
FLC_PRESETS = {
    "DRAFT": ("Draft", "Fast and noisy: 64 VPLs per pixel, coarse interleaving, wide blur", {
        "flc_vpls_per_pixel": 64, "viewport_flc_vpls_per_pixel": 64,
        "flc_tiling": 3, "viewport_flc_tiling": 3, "flc_blur_radius": 5,
        "samples": 16, "viewport_samples": 8}),
    "PREVIEW": ("Preview", "The default balance: 256 VPLs per pixel", {
        "flc_vpls_per_pixel": 256, "viewport_flc_vpls_per_pixel": 256,
        "flc_tiling": 2, "viewport_flc_tiling": 2, "flc_blur_radius": 3,
        "samples": 64, "viewport_samples": 32}),
    "FINAL": ("Final", "Converged first bounce: 1024 VPLs per pixel, fine interleaving, many samples", {
        "flc_vpls_per_pixel": 1024, "viewport_flc_vpls_per_pixel": 512,
        "flc_tiling": 1, "viewport_flc_tiling": 2, "flc_blur_radius": 2,
        "samples": 256, "viewport_samples": 64}),
}

PRESETS_BY_GROUP = {"Forward Light Cuts": FLC_PRESETS}


class BOUNCE_OT_apply_preset(bpy.types.Operator):
    """Set the Forward Light Cuts quality settings to a preset"""

    bl_idname = "bounce.apply_preset"
    bl_label = "Apply Bounce Preset"
    bl_options = {"REGISTER", "UNDO"}

    preset: bpy.props.EnumProperty(
        name="Preset", items=[(key, label, tip) for key, (label, tip, _values) in FLC_PRESETS.items()])

    @classmethod
    def description(cls, _context, properties):
        return FLC_PRESETS[properties.preset][1]

    def execute(self, context):
        props = context.scene.bounce
        for name, value in FLC_PRESETS[self.preset][2].items():
            if hasattr(props, name):
                setattr(props, name, value)
        return {"FINISHED"}


def draw_buttons(layout, group):
    """One button per preset of `group`, above its settings (nothing for groups without presets)."""
    presets = PRESETS_BY_GROUP.get(group)
    if not presets:
        return
    row = layout.row(align=True)
    for key, (label, _tip, _values) in presets.items():
        row.operator(BOUNCE_OT_apply_preset.bl_idname, text=label).preset = key

