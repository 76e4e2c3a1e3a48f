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

# Screen-Space VPL Propagation: the paper's defaults are Preview (256 + 256 VPLs, 8 clusters, 4x4 tiles; Sec. III,
# Table I). Draft halves the costs, Final buys sharper indirect shadows with more clusters (Fig. 2) and keeps at
# least 32 second-bounce VPLs per cluster (Sec. III-D).
SSVP_PRESETS = {
    "DRAFT": ("Draft", "Fast: 128 + 128 VPLs, 4 clusters, 8x8 interleaving, wide blur", {
        "ssvp_vpls": 128, "ssvp_second_vpls": 128, "ssvp_clusters": 4, "ssvp_tiling": 3,
        "ssvp_paraboloid_size": 128, "ssvp_blur_radius": 6, "samples": 4, "viewport_samples": 4}),
    "PREVIEW": ("Preview", "The paper's settings: 256 + 256 VPLs, 8 clusters, 4x4 interleaving", {
        "ssvp_vpls": 256, "ssvp_second_vpls": 256, "ssvp_clusters": 8, "ssvp_tiling": 2,
        "ssvp_paraboloid_size": 256, "ssvp_blur_radius": 4, "samples": 16, "viewport_samples": 16}),
    "FINAL": ("Final", "Converged: 1024 + 2048 VPLs, 32 clusters, 2x2 interleaving, many samples", {
        "ssvp_vpls": 1024, "ssvp_second_vpls": 2048, "ssvp_clusters": 32, "ssvp_tiling": 1,
        "ssvp_paraboloid_size": 512, "ssvp_blur_radius": 2, "samples": 64, "viewport_samples": 32}),
}

# Topology: the paper renders 512 to 2048 VPLs (Table I) on a 256^3 grid (Sec. VI.A). Draft keeps the
# precomputation under a second or two on small scenes; Final is the paper's grid with its largest VPL count.
TOPOLOGY_PRESETS = {
    "DRAFT": ("Draft", "Fast: a 64^3 grid, 256 VPLs, few samples", {
        "topology_resolution": 64, "topology_vpls": 256, "viewport_topology_vpls": 256,
        "topology_cluster_size": 32, "samples": 4, "viewport_samples": 4}),
    "PREVIEW": ("Preview", "A 128^3 grid and 1024 VPLs (the paper: 512 to 2048)", {
        "topology_resolution": 128, "topology_vpls": 1024, "viewport_topology_vpls": 512,
        "topology_cluster_size": 16, "samples": 16, "viewport_samples": 8}),
    "FINAL": ("Final", "The paper's 256^3 grid and 2048 VPLs, many samples", {
        "topology_resolution": 256, "topology_vpls": 2048, "viewport_topology_vpls": 1024,
        "topology_cluster_size": 16, "samples": 64, "viewport_samples": 16}),
}

PRESETS_BY_GROUP = {"Forward Light Cuts": FLC_PRESETS, "Screen-Space VPL Propagation": SSVP_PRESETS,
                    "Topology": TOPOLOGY_PRESETS}


class BOUNCE_OT_apply_preset(bpy.types.Operator):
    """Set a settings group's quality settings to a preset"""

    bl_idname = "bounce.apply_preset"
    bl_label = "Apply Bounce Preset"
    bl_options = {"REGISTER", "UNDO"}

    group: bpy.props.StringProperty(name="Group", default="Forward Light Cuts")
    preset: bpy.props.StringProperty(name="Preset", default="PREVIEW")

    @classmethod
    def description(cls, _context, properties):
        found = PRESETS_BY_GROUP.get(properties.group, {}).get(properties.preset)
        return found[1] if found else "Unknown preset"

    def execute(self, context):
        found = PRESETS_BY_GROUP.get(self.group, {}).get(self.preset)
        if found is None:
            self.report({"ERROR"}, f"No preset {self.preset!r} for {self.group!r}")
            return {"CANCELLED"}
        props = context.scene.bounce
        for name, value in found[2].items():
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
        button = row.operator(BOUNCE_OT_apply_preset.bl_idname, text=label)
        button.group = group
        button.preset = key
