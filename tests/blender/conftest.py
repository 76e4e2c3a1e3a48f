"""Blender test suite: shared fixtures.

Every test drives a real Blender with the freshly built add-on (build/addon/bounce) through `scripts/blender`,
headless (`-b --factory-startup`); Blender-side logic lives in tests/blender/scripts/*.py, run with --python,
and writes EXR/JSON files that the tests read here with numpy and OpenImageIO.

Environment:
  BOUNCE_BLENDER_CHROOT   run Blender inside that chroot (`scripts/chroot run NAME -- scripts/blender ...`):
                          trixie = Blender 4.3, sid = Blender 5.2. Unset: the host's Blender (3.4).
  BOUNCE_BUILD_DIR        the CMake build folder holding addon/bounce (default: <repo>/build); test outputs go there
  BOUNCE_ADDON_BUILD_DIR  the build folder of the add-on instead, when it differs: scripts/test builds the add-on
                          inside each chroot, against that release's libraries (Embree 4 from Debian 13 on)
  BOUNCE_SHARED_SCENES    the third-party scenes (default: <repo>/../shared/scenes)
  BOUNCE_TEST_TIMEOUT     seconds one Blender run may take (default 600)

Outputs: <build>/blender-tests/<host|chroot>/ (cleared per session; logs/ holds each Blender run's output,
measurements.json the numbers the tests measured); caches (scene .blend files, Cycles references) under
<build>/blender-cache/<blender version>/; the cross-version images under <build>/version-images/.
"""
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
SCRIPTS = HERE / "scripts"
BUILD = Path(os.environ.get("BOUNCE_BUILD_DIR") or REPO / "build").resolve()
ADDON = Path(os.environ.get("BOUNCE_ADDON_BUILD_DIR") or BUILD).resolve() / "addon" / "bounce"
SHARED_SCENES = Path(os.environ.get("BOUNCE_SHARED_SCENES") or REPO.parent / "shared" / "scenes").resolve()
CHROOT = os.environ.get("BOUNCE_BLENDER_CHROOT") or None
TAG = CHROOT or "host"
OUT_ROOT = BUILD / "blender-tests" / TAG
TIMEOUT = float(os.environ.get("BOUNCE_TEST_TIMEOUT", "600"))

sys.path.insert(0, str(HERE))

# Numbers measured by the tests: name -> value; written to measurements.json and printed at the end.
MEASUREMENTS = {}


def record(name, value):
    MEASUREMENTS[name] = value


class BlenderResult:
    def __init__(self, cmd, returncode, stdout, stderr, seconds, log):
        self.cmd, self.returncode, self.stdout, self.stderr = cmd, returncode, stdout, stderr
        self.seconds, self.log = seconds, log

    @property
    def output(self):
        return self.stdout + "\n" + self.stderr

    def tail(self, lines=40):
        return "\n".join(self.output.strip().splitlines()[-lines:])

    def describe(self):
        return (f"Blender exited {self.returncode} after {self.seconds:.1f} s; log {self.log}\n"
                f"command: {' '.join(map(str, self.cmd))}\n--- output tail ---\n{self.tail()}")


class Blender:
    """Runs Blender (host or chroot) with or without the Bounce add-on."""

    def __init__(self, chroot):
        self.chroot = chroot
        self.log_dir = OUT_ROOT / "logs"
        self.info = None
        self._count = 0

    def command(self, args, addon=True, factory=True, background=True):
        prefix = [str(REPO / "scripts" / "chroot"), "run", self.chroot, "--"] if self.chroot else []
        exe = [str(REPO / "scripts" / "blender")] if addon else [os.environ.get("BLENDER", "blender")]
        if self.chroot and not addon:
            exe = ["blender"]
        flags = (["-b"] if background else []) + (["--factory-startup"] if factory else [])
        return prefix + exe + flags + [str(a) for a in args]

    def run(self, args, name="blender", addon=True, factory=True, env=None, timeout=None, check=True,
            python_exit_code=True, background=True):
        """Run Blender; returns a BlenderResult. check: fail the test when the exit status is not 0."""
        args = list(args)
        if python_exit_code:
            args = ["--python-exit-code", "1"] + args
        cmd = self.command(args, addon=addon, factory=factory, background=background)
        return self.run_command(cmd, name=name, env=env, timeout=timeout, check=check)

    def run_command(self, cmd, name="command", env=None, timeout=None, check=True, in_chroot=False):
        """Run a command line (in the chroot when in_chroot and a chroot is in use); returns a BlenderResult."""
        if in_chroot and self.chroot:
            cmd = [str(REPO / "scripts" / "chroot"), "run", self.chroot, "--"] + list(cmd)
        cmd = [str(c) for c in cmd]
        full_env = {k: v for k, v in os.environ.items() if not k.startswith("BLENDER_USER_")}
        full_env.setdefault("BOUNCE_BUILD_DIR", str(BUILD))
        # Auto's cost model is not kept between Blender runs unless a test asks (test_auto.py): a plan must not
        # depend on the tests that ran before.
        full_env.setdefault("BOUNCE_COST_MODEL_DIR", "off")
        if env:
            full_env.update(env)
        self._count += 1
        self.log_dir.mkdir(parents=True, exist_ok=True)
        log = self.log_dir / f"{self._count:03d}-{re.sub(r'[^A-Za-z0-9_.-]+', '_', name)}.log"
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=str(REPO), env=full_env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                stdin=subprocess.DEVNULL, text=True, errors="replace", start_new_session=True)
        try:
            stdout, stderr = proc.communicate(timeout=timeout or TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            stdout, stderr = proc.communicate()
            stderr += f"\n[test harness] killed after {timeout or TIMEOUT:.0f} s"
            proc.returncode = -9
        seconds = time.perf_counter() - start
        log.write_text(f"$ {' '.join(cmd)}\n# exit {proc.returncode}, {seconds:.1f} s\n"
                       f"--- stdout ---\n{stdout}\n--- stderr ---\n{stderr}\n")
        result = BlenderResult(cmd, proc.returncode, stdout, stderr, seconds, log)
        if check and proc.returncode != 0:
            pytest.fail(result.describe(), pytrace=False)
        return result

    def script(self, script, script_args=(), blend=None, name=None, **kw):
        """Run tests/blender/scripts/SCRIPT (after opening BLEND, if given) with arguments after `--`."""
        args = ([str(blend)] if blend else []) + ["--python", str(SCRIPTS / script), "--"]
        args += [str(a) for a in script_args]
        return self.run(args, name=name or Path(script).stem, **kw)

    def render(self, config, out_base, blend=None, name=None):
        """Run scripts/render.py on CONFIG (after opening BLEND, if given), writing its image to OUT_BASE and its
        info to OUT_BASE.json; return (the info, with the EXR's path as "exr", and the run's BlenderResult)."""
        out_base = Path(out_base)
        config_path = out_base.with_name(out_base.name + ".config.json")
        info_path = out_base.with_name(out_base.name + ".json")
        config_path.write_text(json.dumps(dict(config, out=str(out_base), info=str(info_path))))
        result = self.script("render.py", [config_path], blend=blend, name=name or out_base.name)
        return json.loads(info_path.read_text()), result

    def render_cases(self, script, spec, out, record_name, name):
        """Write `spec` to OUT/cases.json, run SCRIPT with (cases.json, OUT), return OUT/RECORD_NAME parsed."""
        out.mkdir(parents=True, exist_ok=True)
        (out / "cases.json").write_text(json.dumps(spec, indent=1))
        self.script(script, [out / "cases.json", out], name=name)
        return json.loads((out / record_name).read_text())

    @property
    def version(self):
        return tuple(self.info["version"])

    @property
    def version_string(self):
        return ".".join(str(v) for v in self.version)


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: renders that take more than a few seconds")
    config.addinivalue_line(
        "markers", "core: checks the native core's numbers through Blender (convergence, determinism, every method "
        "on an input the export already handled): the same on every Blender version, so scripts/test runs it on "
        "the host's Blender only")


def pytest_sessionstart(session):
    if OUT_ROOT.exists():
        shutil.rmtree(OUT_ROOT, ignore_errors=True)
    OUT_ROOT.mkdir(parents=True, exist_ok=True)


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if not MEASUREMENTS:
        return
    OUT_ROOT.mkdir(parents=True, exist_ok=True)
    path = OUT_ROOT / "measurements.json"
    path.write_text(json.dumps(MEASUREMENTS, indent=1, sort_keys=True) + "\n")
    terminalreporter.section(f"Bounce measurements ({TAG}; {path})")
    for name in sorted(MEASUREMENTS):
        value = MEASUREMENTS[name]
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        terminalreporter.write_line(f"  {name:<58} {text}")


@pytest.fixture(scope="session")
def blender():
    """The Blender under test, with the add-on checked to load (scene.bounce and the BOUNCE engine exist)."""
    if not (ADDON / "__init__.py").is_file() or not (ADDON / "libbounce.so").is_file():
        pytest.exit(f"no built add-on at {ADDON}: build first (cmake -S . -B build -G Ninja && "
                    "cmake --build build)", returncode=3)
    b = Blender(CHROOT)
    probe = OUT_ROOT / "probe.json"
    b.script("probe.py", [probe], name="probe")
    b.info = json.loads(probe.read_text())
    if not b.info.get("engine_registered") or not b.info.get("settings"):
        pytest.exit(f"the Bounce add-on did not load in Blender {b.info.get('version')}: see {b.log_dir}",
                    returncode=3)
    record("blender.version", b.version_string)
    return b


@pytest.fixture(scope="session")
def out_root():
    return OUT_ROOT


@pytest.fixture
def out_dir(request):
    """A fresh folder for one test under <build>/blender-tests/<tag>/ (visible inside the chroots too)."""
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", request.node.name)
    path = OUT_ROOT / name
    shutil.rmtree(path, ignore_errors=True)
    path.mkdir(parents=True)
    return path


@pytest.fixture(scope="session")
def cache_dir(blender):
    path = BUILD / "blender-cache" / blender.version_string
    path.mkdir(parents=True, exist_ok=True)
    return path


@pytest.fixture(scope="session")
def shared_scenes():
    if not (SHARED_SCENES / "setups" / "cornell.py").is_file():
        pytest.skip(f"shared scenes not found at {SHARED_SCENES} (set BOUNCE_SHARED_SCENES); "
                    "tests that need third-party scenes are skipped")
    return SHARED_SCENES


def file_digest(*paths):
    h = hashlib.sha256()
    for p in paths:
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


CORNELL_RES = 128


def build_setup_scene(blender, shared_scenes, name, data_files, args):
    """A .blend built by shared/scenes/setups/NAME.py, once per setup version and arguments.

    Always built with the host's Blender (3.4) and opened by every version: the setup scripts use
    Material.shadow_method, which Blender 4.2 removed, so they fail in the chroots' Blender 4.3 / 5.2."""
    setup = shared_scenes / "setups"
    key = file_digest(setup / f"{name}.py", setup / "common.py", *(shared_scenes / f for f in data_files))
    directory = BUILD / "blender-cache" / "scenes"
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{name}-{'-'.join(map(str, args))}-{key}.blend"
    if not path.is_file():
        tmp = path.with_suffix(".tmp.blend")
        host = Blender(None)
        host.log_dir = blender.log_dir
        host.run(["--python", str(setup / f"{name}.py"), "--", "--out", str(tmp)] + [str(a) for a in args],
                 name=f"{name}-setup", addon=False)
        tmp.rename(path)
    return path


@pytest.fixture(scope="session")
def cornell_blend(blender, shared_scenes):
    """shared/scenes/setups/cornell.py's scene at CORNELL_RES."""
    return build_setup_scene(blender, shared_scenes, "cornell", ["cornell_box/CornellBox-Original.obj"],
                             ["--res", CORNELL_RES])


@pytest.fixture(scope="session")
def sponza_blend(blender, shared_scenes):
    """shared/scenes/setups/sponza.py's scene (Crytek Sponza: textures, alpha cut-outs, instances) at 160x90."""
    return build_setup_scene(blender, shared_scenes, "sponza", ["crytek_sponza/Sponza.gltf"],
                             ["--width", 160, "--height", 90])


# ---- EXR reading ------------------------------------------------------------------------------------------

def read_exr(path):
    """{channel name: HxW float32 array} of a (multilayer) EXR, every part of it (Blender 5 writes multilayer
    EXRs as one part per pass unless use_exr_interleave is set); rows top first."""
    import numpy as np
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise AssertionError(f"cannot open {path}: {oiio.geterror()}")
    channels = {}
    try:
        subimage = 0
        while inp.seek_subimage(subimage, 0):
            spec = inp.spec()
            pixels = np.asarray(inp.read_image(subimage, 0, 0, spec.nchannels, oiio.FLOAT), dtype=np.float32)
            pixels = pixels.reshape(spec.height, spec.width, spec.nchannels)
            channels.update({name: pixels[:, :, i] for i, name in enumerate(spec.channelnames)})
            subimage += 1
    finally:
        inp.close()
    return channels


class MissingChannels(Exception):
    """A pass is not in the EXR (not an AssertionError: must not satisfy xfail(raises=AssertionError))."""


# Blender 5.0 renamed Cycles' passes in files: DiffCol -> "Diffuse Color", ...
PASS_ALIASES = {"DiffCol": ("Diffuse Color",), "DiffDir": ("Diffuse Direct",), "DiffInd": ("Diffuse Indirect",)}


def thirds_over(image, reference):
    """The mean of `image` over `reference`'s in the left, middle and right thirds of the view."""
    width = image.shape[1]
    return [float(image[:, a:b].mean() / reference[:, a:b].mean())
            for a, b in ((0, width // 3), (width // 3, 2 * width // 3), (2 * width // 3, width))]


def assert_ray_checks_reach_every_pair(what, rule, checked, every_pair, key):
    """Ray Checks' image (`checked`) within 5 % of a shadow ray per pair's in every third of the view, finite and
    never below zero; prints `rule`'s thirds beside it and records Ray Checks' under `key`."""
    import numpy as np

    assert np.all(np.isfinite(checked)) and checked.min() >= 0.0
    rule_over_rays, checked_over_rays = thirds_over(rule, every_pair), thirds_over(checked, every_pair)
    print(f"{what} over a shadow ray per pair, left / middle / right third: the rule "
          + " / ".join(f"{t:.3f}" for t in rule_over_rays) + ", Ray Checks "
          + " / ".join(f"{t:.3f}" for t in checked_over_rays))
    record(key, [round(t, 4) for t in checked_over_rays])
    assert all(abs(t - 1.0) < 0.05 for t in checked_over_rays)


def layer_pass(channels, pass_name, components="RGB", layer="ViewLayer"):
    """An HxWxC array of one pass (e.g. 'Combined', 'RGB') from read_exr's dict."""
    import numpy as np

    for name in (pass_name,) + PASS_ALIASES.get(pass_name, ()):
        names = [f"{layer}.{name}.{c}" for c in components]
        if all(n in channels for n in names):
            break
    else:
        raise MissingChannels(f"no {pass_name} pass ({components}); present: {sorted(channels)}")
    return np.stack([channels[n] for n in names], axis=-1)
