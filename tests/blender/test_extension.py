"""(g) The extension (Blender 4.2+): build the zip from build/addon/bounce with this Blender, validate it, install
it into a temporary BLENDER_USER_RESOURCES, and render the demo with the installed extension enabled (Blender
started without scripts/blender, i.e. not through the legacy add-on path)."""
import json
import zipfile

import numpy as np
import pytest

from conftest import ADDON, layer_pass, read_exr, record


@pytest.fixture
def needs_extensions(blender):
    if blender.version < (4, 2, 0):
        pytest.skip(f"Blender {blender.version_string} has no extension platform (4.2+)")


def ext(blender, args, name, env=None, **kw):
    return blender.run(["--command", "extension"] + list(args), name=name, addon=False, factory=False,
                       python_exit_code=False, env=env, **kw)


def test_extension_build_install_render(blender, needs_extensions, out_dir):
    result = ext(blender, ["validate", ADDON], "ext-validate-dir")
    assert "Success" in result.output, result.describe()

    dist = out_dir / "dist"
    dist.mkdir()
    ext(blender, ["build", "--source-dir", ADDON, "--output-dir", dist], "ext-build")
    zips = sorted(dist.glob("*.zip"))
    assert len(zips) == 1, f"expected one zip in {dist}: {zips}"
    package = zips[0]
    record("extension.zip", package.name)
    names = zipfile.ZipFile(package).namelist()
    assert "libbounce.so" in names and "__init__.py" in names and "blender_manifest.toml" in names, names
    assert not [n for n in names if "__pycache__" in n], names

    result = ext(blender, ["validate", package], "ext-validate-zip")
    assert "Success" in result.output, result.describe()

    user = out_dir / "user"
    env = {"BLENDER_USER_RESOURCES": str(user)}
    result = blender.run(["--command", "extension", "install-file", "-r", "user_default", "-e", package],
                         name="ext-install", addon=False, factory=False, python_exit_code=False, env=env)
    installed = user / "extensions" / "user_default" / "bounce"
    assert (installed / "libbounce.so").is_file(), f"not installed in {installed}\n{result.describe()}"

    render_out = out_dir / "render"
    blender.script("ext_render.py", [render_out], name="ext-render", addon=False, factory=False, env=env)
    info = json.loads((render_out / "ext.json").read_text())
    print("extension:", info)
    assert "bl_ext.user_default.bounce" in info["addons"], info
    assert "bounce" not in info["addons"], "the legacy add-on must not be enabled here"
    assert info["engine_module"] and info["engine_module"].startswith("bl_ext.user_default.bounce"), info
    rgb = layer_pass(read_exr(info["exr"]), "Combined", "RGB")
    assert np.all(np.isfinite(rgb)) and rgb.mean() > 0.01, f"the demo render is black: mean {rgb.mean():.4g}"
    record("extension.demo_mean", round(float(rgb.mean()), 5))
