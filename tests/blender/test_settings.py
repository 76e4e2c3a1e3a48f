"""The settings as a user meets them: the common `bounces` setting serves every method with bounces, and files saved
before it existed keep their values (`topology_bounces` became `bounces`; addon/versioning.py)."""
import json

# (raw ID properties an old file stored in scene.bounce, the expected `bounces` after opening it)
OLD_FILES = {
    "topology_only": ({"method": 4, "topology_bounces": 3}, 3),            # method 4 = TOPOLOGY
    "ssvp_with_both": ({"method": 3, "bounces": 1, "topology_bounces": 5}, 1),  # SSVP read `bounces`
    "topology_with_both": ({"method": 4, "bounces": 1, "topology_bounces": 4}, 4),
    "ssvp_default_bounces": ({"method": 3, "topology_bounces": 6}, 6),    # `bounces` never set: the only value
}

WRITE = """
import bpy, json, sys
cases = json.loads(sys.argv[-2])
for name, (raw, _expected) in cases.items():
    scene = bpy.data.scenes.new(name)
    scene.render.engine = 'BOUNCE'
    for key, value in raw.items():
        scene.bounce[key] = value  # raw ID properties, as an older Bounce stored them
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1])
"""

READ = """
import bpy, json, sys
found = {s.name: {'bounces': s.bounce.bounces, 'keys': sorted(s.bounce.keys())} for s in bpy.data.scenes}
open(sys.argv[-1], 'w').write(json.dumps(found))
"""


def test_the_one_bounces_setting_spans_every_method(blender):
    assert "bounces" in blender.info["settings"]
    assert "topology_bounces" not in blender.info["settings"]


def test_old_files_keep_topology_bounces(blender, out_dir):
    old = out_dir / "old.blend"
    blender.run(["--python-expr", WRITE, "--", json.dumps(OLD_FILES), old], name="old-file")
    found_path = out_dir / "found.json"
    blender.run([old, "--python-expr", READ, "--", found_path], name="old-file-open")
    found = json.loads(found_path.read_text())
    for name, (_raw, expected) in OLD_FILES.items():
        assert found[name]["bounces"] == expected, (name, found[name])
        assert "topology_bounces" not in found[name]["keys"], (name, found[name])
