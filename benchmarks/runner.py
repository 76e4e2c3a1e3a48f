"""Scene building, Blender runs and the Cycles reference cache of scripts/benchmark (host Python 3.11).

Blender runs (scripts/blender, so the freshly built add-on is enabled) render whole job lists at once: one
Blender start per scene, not per render. Scenes are built with the host Blender (3.4): the shared setups'
common.py does not run on 4.2+. Set BOUNCE_SCENE_BLENDER to use another one.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
HERE = REPO / "benchmarks"
BUILD = Path(os.environ.get("BOUNCE_BUILD_DIR") or REPO / "build").resolve()
SHARED = Path(os.environ.get("BOUNCE_SHARED_DIR") or REPO.parent / "shared").resolve()
SETUPS = SHARED / "scenes" / "setups"
RENDER_SCRIPT = HERE / "blender_render.py"
DRAGON_SCRIPT = HERE / "dragon_scene.py"
TWO_ROOMS_SCRIPT = HERE / "two_rooms_scene.py"
SUNLIT_INTERIOR_SCRIPT = HERE / "sunlit_interior_scene.py"
OPEN_GROUND_SCRIPT = HERE / "open_ground_scene.py"
RELIT_SCRIPT = HERE / "relit_scene.py"
# The scenes built by this folder's scripts: name -> (script, its arguments).
LOCAL_SCENES = {"two-rooms": (TWO_ROOMS_SCRIPT, []), "two-rooms-wall": (TWO_ROOMS_SCRIPT, ["--wall"]),
                "sunlit-interior": (SUNLIT_INTERIOR_SCRIPT, []), "open-ground": (OPEN_GROUND_SCRIPT, [])}
# Scenes relit from another (relit_scene.py): name -> (the scene it starts from, relit_scene.py's arguments).
RELIT_SCENES = {"cornell-emissive": ("cornell", ["--lighting", "emissive-panel"]),
                "sponza-hdri": ("sponza", ["--lighting", "hdri", "--hdri", "courtyard.exr"]),
                "sunlit-interior-sky": ("sunlit-interior", ["--lighting", "sky", "--hdri", "sunrise.exr"]),
                "cornell-white": ("cornell", ["--albedo", "white"]),
                "cornell-black": ("cornell", ["--albedo", "near-black"]),
                # Held out: in no suite, and no setting or fix was measured on them before they were first run
                # (docs/accuracy-history.md, "Scenes nobody tuned for").
                "sponza-forest": ("sponza", ["--lighting", "hdri", "--hdri", "forest.exr"]),
                "open-ground-city": ("open-ground", ["--lighting", "sky", "--hdri", "city.exr"]),
                "cornell-emissive-white": ("cornell", ["--lighting", "emissive-panel", "--albedo", "white"]),
                "sunlit-interior-forest": ("sunlit-interior", ["--lighting", "hdri", "--hdri", "forest.exr"])}
# Seeds differ so a reference's noise is independent of the Cycles renders measured against it.
REFERENCE_SEED = 7919
CYCLES_SEED = 0
# Bumped when the reference recipe changes, so cached references are not reused across recipes.
REFERENCE_RECIPE = "oracle-k{bounces}-v1"
CPU_REFERENCE_RECIPE = "cpu-model-v1"
CPU_REFERENCE_TOOL = BUILD / "bounce_reference_render"


def log(message):
    print(f"benchmark: {message}", flush=True)


def scene_blender():
    return os.environ.get("BOUNCE_SCENE_BLENDER") or ("/usr/bin/blender" if Path("/usr/bin/blender").exists()
                                                      else "blender")


def _digest(*parts):
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else str(part).encode())
    return h.hexdigest()[:12]


class Scene:
    """A scene to render: `name` for tables, `blend` (None: the factory scene), `key` for the reference cache
    (changes when the script that builds the scene changes), `extra_triangles` for the sync grid, `camera` the
    camera object every render of it looks through (None: the .blend's active camera), `sources` the light source
    classes that alone light it (None: every light; else '+'-joined bl_common.LIGHT_SOURCE_CLASSES)."""

    def __init__(self, name, blend=None, key=None, extra_triangles=0, triangles_hint=None, camera=None):
        self.name, self.blend, self.key = name, blend, key or name
        self.extra_triangles, self.triangles_hint, self.camera = extra_triangles, triangles_hint, camera
        self.sources = None


def _build(name, script, args, cache):
    blend = cache / f"{name}.blend"
    key = f"{name}-{_digest(Path(script).read_bytes(), *args)}"
    stamp = cache / f"{name}.key"
    if blend.exists() and stamp.exists() and stamp.read_text() == key:
        return blend, key
    cache.mkdir(parents=True, exist_ok=True)
    log(f"building scene {name} with {scene_blender()}")
    command = [scene_blender(), "-b", "--factory-startup", "--python-exit-code", "1", "--python", str(script),
               "--", "--out", str(blend), *map(str, args)]
    logfile = cache / f"{name}.log"
    with open(logfile, "w") as out:
        if subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, cwd=REPO).returncode != 0:
            sys.exit(f"scripts/benchmark: building {name} failed, see {logfile}")
    stamp.write_text(key)
    return blend, key


def standard_scene(name, cache):
    """cornell, sponza (from ../shared/scenes/setups), two-rooms, two-rooms-wall, sunlit-interior, open-ground
    (LOCAL_SCENES), cornell-emissive, sponza-hdri, sunlit-interior-sky, cornell-white, cornell-black, the held-out
    sponza-forest, open-ground-city, cornell-emissive-white, sunlit-interior-forest (RELIT_SCENES) or grid (the
    factory scene plus 1M triangles). 'NAME:CAMERA' (e.g. two-rooms-wall:CameraA) is scene NAME seen
    through its camera object CAMERA; its references are cached apart. 'NAME@SOURCES' (e.g. sunlit-interior-sky@world,
    cornell@lamps+world) is NAME lit by those source classes alone (lamps, world, emission), in Cycles and Bounce
    alike: light adds up, so that scene's components are those classes' share of NAME's."""
    base_name, _, sources = name.partition("@")
    if sources:
        scene = standard_scene(base_name, cache)
        scene.name, scene.key, scene.sources = name, f"{scene.key}-only-{sources}", sources
        return scene
    if name == "grid":
        return Scene("grid-1M", extra_triangles=1_000_000)
    if name.startswith("grid-"):  # grid-<triangles>, e.g. grid-100k for quick runs
        count = int(float(name[5:].lower().replace("k", "e3").replace("m", "e6")))
        return Scene(name, extra_triangles=count)
    base, _, camera = name.partition(":")
    if base in RELIT_SCENES:
        source, lighting = RELIT_SCENES[base]
        original = standard_scene(source, cache)
        blend, key = _build(base, RELIT_SCRIPT, ["--base", original.blend, "--base-key", original.key, *lighting],
                            cache)
        return Scene(name, blend, f"{key}-{camera}" if camera else key, camera=camera or None)
    script, args = LOCAL_SCENES.get(base, (SETUPS / f"{base}.py", []))
    if not script.exists():
        sys.exit(f"scripts/benchmark: no scene '{base}' ({script} not found)")
    blend, key = _build(base, script, args, cache)
    return Scene(name, blend, f"{key}-{camera}" if camera else key, camera=camera or None)


def dragon_scene(copies, instancing, cache):
    name = f"dragons-{copies}-{instancing}"
    blend, key = _build(name, DRAGON_SCRIPT, ["--copies", copies, "--instancing", instancing], cache)
    return Scene(name, blend, key, triangles_hint=copies * 100_000 + 2)


def blender_command(blend, jobs_file, script=RENDER_SCRIPT, screen=None):
    """Blender in the background, or with its GUI on an Xvfb screen of `screen` (width, height)."""
    scene = [str(blend)] if blend else ["--factory-startup"]
    blender = [str(REPO / "scripts" / "blender"), *scene, "--python-exit-code", "1", "--python", str(script), "--",
               str(jobs_file)]
    if screen is None:
        return blender[:1] + ["-b"] + blender[1:]
    return ["xvfb-run", "-a", "-s", f"-screen 0 {screen[0]}x{screen[1]}x24"] + blender


def run_blender(scene, jobs, work, info=None):
    """Renders `jobs` in one Blender run (through the scene's camera, if it names one); returns the records it
    wrote. Progress lines pass through."""
    if scene.camera:
        jobs = [dict(job, camera=scene.camera) for job in jobs]
    if scene.sources:
        jobs = [dict(job, sources=scene.sources) for job in jobs]
    return run_script(scene, RENDER_SCRIPT, {"info": str(info) if info else None,
                                             "extra_triangles": scene.extra_triangles, "jobs": jobs}, work)


def run_script(scene, script, config, work, screen=None):
    """Runs a Blender-side benchmark `script` on `scene` with `config` (plus "records": the file it appends JSON
    lines to), in the background or on an Xvfb `screen`; returns those records. Progress lines pass through."""
    work.mkdir(parents=True, exist_ok=True)
    stem = f"{scene.name}-{int(time.time() * 1000) % 10**9}"
    records_file = work / f"{stem}.records.jsonl"
    records_file.unlink(missing_ok=True)
    jobs_file = work / f"{stem}.jobs.json"
    jobs_file.write_text(json.dumps(dict(config, records=str(records_file)), indent=1))
    logfile = work / f"{stem}.log"
    # Auto's cost model starts empty in each run, as the suite's figures were measured; BOUNCE_COST_MODEL_DIR in
    # the caller's environment keeps one instead.
    env = dict(os.environ, BOUNCE_BUILD_DIR=str(BUILD))
    env.setdefault("BOUNCE_COST_MODEL_DIR", "off")
    with open(logfile, "w") as out:
        process = subprocess.Popen(blender_command(scene.blend, jobs_file, script, screen), cwd=REPO, env=env, text=True,
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, errors="replace")
        for line in process.stdout:
            out.write(line)
            if line.startswith(("benchmark:", "temporal:")) or "Error" in line:
                print(f"  {scene.name}: {line.rstrip()}", flush=True)
        process.wait()
    if process.returncode != 0:
        sys.exit(f"scripts/benchmark: Blender failed on {scene.name} (exit {process.returncode}), see {logfile}")
    if not records_file.exists():
        return []
    return [json.loads(line) for line in records_file.read_text().splitlines() if line.strip()]


def probe(work):
    """Blender's version and the GL renderer Bounce gets, from one empty Blender run."""
    info = work / "probe.json"
    run_blender(Scene("probe"), [], work, info=info)
    return json.loads(info.read_text())


def _uncached(resolutions, path_of, what):
    """(width, height, path) of each resolution whose cached file `path_of(width, height)` is missing."""
    for width, height in sorted(set(resolutions)):
        path = path_of(width, height)
        if path.exists():
            log(f"{what} {path.name}: cached")
        else:
            yield width, height, path


class References:
    """Cycles references with exactly `bounces` diffuse bounces, cached as EXRs keyed by scene, resolution, Blender
    version, samples and bounces."""

    def __init__(self, folder, blender_version, samples, device, bounces=1):
        self.folder, self.blender_version, self.samples, self.device = Path(folder), blender_version, samples, device
        self.bounces = bounces

    def path(self, scene, width, height):
        return self.folder / (f"{scene.key}-{width}x{height}-blender{self.blender_version}-"
                              f"cycles{self.samples}-{REFERENCE_RECIPE.format(bounces=self.bounces)}.exr")

    def missing_jobs(self, scene, resolutions):
        """Jobs that render the references `scene` lacks at `resolutions` (so they join the scene's run)."""
        jobs = []
        for width, height, path in _uncached(resolutions, lambda w, h: self.path(scene, w, h), "reference"):
            log(f"reference {path.name}: rendering with Cycles, {self.samples} samples, {self.bounces} bounces")
            jobs.append(cycles_job(width, height, self.samples, REFERENCE_SEED, self.device, path,
                                   {"label": f"reference {width}x{height}", "role": "reference"}, bounces=self.bounces))
        return jobs


class CpuReferences:
    """The CPU model of FLC's target (native/reference, continuous mode: the limit of jittered VPLs) of each
    scene, cached as RGBA EXRs: RGB the indirect radiance a white receiver reflects, A whether the pixel sees
    a surface. Multiplied by a render's own Albedo pass, it is the Indirect pass that render should converge to.
    Made in two steps: a Blender job writes the scene (cpu_reference_export.py), then bounce_reference_render
    (built with the native tests) renders it on every core. The exported scene stays beside the reference
    (`*.scene.bin`), for bounce_scene_bench on machines without Blender."""

    def __init__(self, folder, points, light_samples=64):
        self.folder, self.points, self.light_samples = Path(folder), points, light_samples
        self.pending = []
        # The cache key follows the model's sources, so an edited model is never answered from the cache.
        self.source = _digest(*(p.read_bytes() for p in sorted((REPO / "native" / "reference").glob("*.*"))),
                              (HERE / "cpu_reference_export.py").read_bytes())

    def path(self, scene, width, height):
        return self.folder / (f"{scene.key}-{width}x{height}-cpu{self.points}-{self.light_samples}-"
                              f"{self.source}-{CPU_REFERENCE_RECIPE}.exr")

    def missing_jobs(self, scene, resolutions):
        if not CPU_REFERENCE_TOOL.exists():
            sys.exit(f"scripts/benchmark: {CPU_REFERENCE_TOOL} is missing: it is built with the native tests "
                     "(scripts/install-deps installs Embree and GoogleTest), or pass --no-cpu-reference")
        jobs = []
        for width, height, path in _uncached(resolutions, lambda w, h: self.path(scene, w, h), "CPU reference"):
            log(f"CPU reference {path.name}: exporting the scene, then rendering {self.points} points")
            self.folder.mkdir(parents=True, exist_ok=True)
            exported = path.with_suffix(".scene.bin")
            self.pending.append((exported, path, width, height))
            jobs.append({"engine": "CPU_REFERENCE", "width": width, "height": height,
                         "cpu_reference": {"scene": str(exported), "points": self.points,
                                           "light_samples": self.light_samples}})
        return jobs

    def complete(self, work):
        """Renders the scenes the Blender run exported."""
        import numpy as np
        import OpenImageIO as oiio
        for exported, path, width, height in self.pending:
            raw = exported.with_suffix(".raw")
            logfile = work / f"{path.stem}.log"
            start = time.perf_counter()
            with open(logfile, "w") as out:
                if subprocess.run([str(CPU_REFERENCE_TOOL), str(exported), str(raw)], stdout=out,
                                  stderr=subprocess.STDOUT).returncode != 0:
                    sys.exit(f"scripts/benchmark: the CPU reference failed, see {logfile}")
            pixels = np.fromfile(raw, dtype="<f4").reshape(height, width, 4)[::-1]  # rows top to bottom
            image = oiio.ImageBuf(oiio.ImageSpec(width, height, 4, oiio.FLOAT))
            image.set_pixels(oiio.ROI(0, width, 0, height), np.ascontiguousarray(pixels))
            partial = path.with_suffix(".partial.exr")
            if not image.write(str(partial)):
                sys.exit(f"scripts/benchmark: cannot write {partial}: {image.geterror()}")
            os.replace(partial, path)
            raw.unlink()
            log(f"CPU reference {path.name}: {time.perf_counter() - start:.1f} s")
        self.pending = []


def cycles_job(width, height, samples, seed, device, exr, meta, repeats=1, bounces=1):
    return {"engine": "CYCLES", "width": width, "height": height, "repeats": repeats, "exr": str(exr) if exr else None,
            "cycles": {"samples": samples, "seed": seed, "device": device, "bounces": bounces}, "meta": meta}


def bounce_job(width, height, settings, repeats, exr, meta):
    return {"engine": "BOUNCE", "width": width, "height": height, "repeats": repeats, "bounce": settings,
            "exr": str(exr) if exr else None, "meta": meta}


def ensure_built():
    if not (BUILD / "addon" / "bounce" / "libbounce.so").exists():
        log(f"no build in {BUILD}: running scripts/build")
        subprocess.run([str(REPO / "scripts" / "build"), str(BUILD)], check=True)


def clear(folder):
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True, exist_ok=True)
