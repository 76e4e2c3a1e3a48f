"""Every module the add-on imports at run time is installed by `scripts/install-deps --minimal` (the demo's set) and by
every chroot's setup: Debian's blender does not depend on python3-numpy, and a bare Debian 12 once failed the demo
for want of it. The fresh-machine stage (scripts/fresh-machine) proves the same end to end, on a bare root."""
import ast
import subprocess
import sys

import pytest

from conftest import REPO

ADDON = REPO / "addon"
# Modules Blender provides to add-ons itself.
BLENDER_MODULES = {"bpy", "bpy_extras", "gpu", "gpu_extras", "mathutils", "bl_math", "bmesh", "addon_utils", "bgl",
                   "bl_ui", "aud", "freestyle", "idprop", "imbuf"}
# Debian's package for each third-party module the add-on may import.
DEBIAN_PACKAGES = {"numpy": "python3-numpy", "OpenImageIO": "python3-openimageio"}


def addon_imports():
    """Top-level names of the absolute imports in the add-on's sources, with the first file that imports each."""
    found = {}
    for path in sorted(ADDON.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module]
            else:
                continue
            for name in names:
                found.setdefault(name.split(".")[0], path.relative_to(REPO))
    return found


def third_party_imports():
    return {name: path for name, path in addon_imports().items()
            if name not in sys.stdlib_module_names and name not in BLENDER_MODULES}


def test_the_scan_finds_numpy():
    assert "numpy" in third_party_imports(), "the import scan misses numpy, which final.py imports"


def test_every_third_party_import_has_a_debian_package():
    unknown = {name: str(path) for name, path in third_party_imports().items() if name not in DEBIAN_PACKAGES}
    assert not unknown, f"add-on imports with no known Debian package (add them to DEBIAN_PACKAGES): {unknown}"


def _listed(command):
    return set(subprocess.run(command, check=True, capture_output=True, text=True).stdout.split())


@pytest.mark.parametrize("where", ["install-deps --minimal", "chroot trixie", "chroot sid"])
def test_run_time_modules_are_installed(where):
    if where.startswith("install-deps"):
        packages = _listed([REPO / "scripts" / "install-deps", "--minimal", "--list"])
    else:
        packages = _listed([REPO / "scripts" / "chroot", "packages", where.split()[1]])
    needed = {DEBIAN_PACKAGES[name] for name in third_party_imports() if name in DEBIAN_PACKAGES}
    assert needed <= packages, f"{where} does not install {sorted(needed - packages)}"
