"""scripts/benchmark: accuracy and time of Bounce's methods, by suite. Run with /usr/bin/python3 (3.11: numpy,
OpenImageIO, matplotlib); Blender renders through scripts/blender (set BLENDER for another Blender).

Each suite renders its scenes through Blender + Bounce over a parameter sweep, records per-stage GPU times,
render wall time and (where the suite measures accuracy) errors against cached Cycles references (with the suite method's number of diffuse bounces),
and writes into --out (default build/benchmark/<suite>/): records.csv (one row per render), records.jsonl,
summary.csv (medians per configuration), <suite>.md (the table printed at the end), <suite>.png, renders/
(EXRs) and logs/.
"""
import argparse
import itertools
import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
try:
    import images  # noqa: E402
except ModuleNotFoundError as missing:  # numpy, OpenImageIO, matplotlib: the test packages, not the demo's
    sys.exit(f"scripts/benchmark: Python module '{missing.name}' is missing; `scripts/install-deps` installs it "
             "(the benchmarks need the test packages, which `scripts/demo` does not install)")
import report  # noqa: E402
import runner  # noqa: E402
from runner import log  # noqa: E402
from suites import SUITES  # noqa: E402


def parse_value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_sets(items):
    """['name=v1,v2', ...] -> {name: [v1, v2]}."""
    sets = {}
    for item in items:
        name, sep, values = item.partition("=")
        if not sep or not values:
            sys.exit(f"scripts/benchmark: --set wants name=value[,value...], got '{item}'")
        sets[name.strip()] = [parse_value(v.strip()) for v in values.split(",")]
    return sets


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="scripts/benchmark", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="suites:\n" + "\n".join(f"  {s.name:11} {s.summary}" for s in SUITES.values()))
    parser.add_argument("--suite", choices=sorted(SUITES), default="sync")
    parser.add_argument("--method", help="scene.bounce.method of the measured renders (default: the suite's)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=V[,V...]",
                        help="a scene.bounce setting; several values sweep it (repeatable; sweeps multiply)")
    parser.add_argument("--scenes", help="comma-separated scene names instead of the suite's: cornell, sponza, two-rooms, "
                        "two-rooms-wall, sunlit-interior, open-ground, cornell-emissive, sponza-hdri, "
                        "sunlit-interior-sky, cornell-white, cornell-black, grid, grid-100k, dragons-N; NAME:CAMERA "
                        "renders NAME through its camera object CAMERA (e.g. "
                        "two-rooms-wall:CameraA); NAME@SOURCES renders NAME lit by those light source classes "
                        "alone (lamps, world, emission, joined by '+'; e.g. sunlit-interior-sky@world)")
    parser.add_argument("--resolution", help="WxH for every scene instead of the suite's")
    parser.add_argument("--repeats", type=int, help="renders per configuration (timings are medians)")
    parser.add_argument("--copies", help="triangles suite: dragon copies, e.g. 1,2,5,10 (100k triangles each)")
    parser.add_argument("--instancing", choices=("collection", "linked"), default="collection",
                        help="how the dragon copies share their mesh")
    parser.add_argument("--cycles-samples", help="error-time suite: Cycles sample counts, e.g. 1,2,4,8")
    parser.add_argument("--reference-samples", type=int, help="Cycles samples of the references (default 1024, "
                        "--quick 32)")
    parser.add_argument("--cycles-device", choices=("CPU", "GPU"), default="CPU")
    parser.add_argument("--references", type=Path, help="reference cache folder "
                        "(default build/benchmark/references)")
    parser.add_argument("--no-cpu-reference", action="store_true",
                        help="FLC suites: skip the CPU model reference (cpuref_* columns)")
    parser.add_argument("--cpu-reference-points", type=int, help="surface points of the CPU model (default "
                        "65536, --quick 4096; every triangle gets at least one)")
    parser.add_argument("--no-errors", action="store_true", help="measure time only")
    parser.add_argument("--quick", action="store_true", help="small resolutions, short sweeps, one repeat")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--report-only", action="store_true",
                        help="write the table, CSVs and plot again from the records.jsonl of an earlier run in --out")
    return parser.parse_args(argv)


class Context:
    """What a suite's report needs: the suite, its output folder, the swept setting names, a title, and the
    configurations left out (a sentence each)."""

    def __init__(self, suite, out, swept, title, skipped=()):
        self.suite, self.out, self.swept, self.title, self.skipped = suite, out, swept, title, list(skipped)

    @staticmethod
    def summarise(records, keys):
        return report.summarise([r for r in records if r.get("role") == "measure"], keys)


def plan_scenes(args, suite, cache):
    if args.scenes:
        preferred, other = (suite.quick_scenes, suite.scenes) if args.quick else (suite.scenes, suite.quick_scenes)
        known = {name: (w, h) for name, w, h in other + preferred}
        fallback = (suite.quick_scenes if args.quick else suite.scenes)[0][1:]
        wanted = [(name, *known.get(name, fallback)) for name in args.scenes.split(",")]
    elif args.copies:
        size = (suite.quick_scenes if args.quick else suite.scenes)[0][1:]
        wanted = [(f"dragons-{n}", *size) for n in args.copies.split(",")]
    else:
        wanted = suite.quick_scenes if args.quick else suite.scenes
    if args.resolution:
        width, height = (int(v) for v in args.resolution.lower().split("x"))
        wanted = [(name, width, height) for name, _, _ in wanted]
    scenes = []
    for name, width, height in wanted:
        if name.startswith("dragons-"):
            scene = runner.dragon_scene(int(name.split("-")[1]), args.instancing, cache)
        else:
            scene = runner.standard_scene(name, cache)
        scenes.append((scene, width, height))
    return scenes


def sweep(args, suite, settings):
    """The configurations: the suite's list of configurations (a method and its settings each; --method keeps
    that method's), else its method, each with the product of every swept setting; the names that vary, for the
    tables; and a sentence for each listed configuration left out because `settings` (scene.bounce's) lacks one
    of its settings (a setting still to come), so that a suite runs on before the setting exists."""
    sets = dict(suite.sets)
    if args.quick:
        sets.update(suite.quick_sets)
    skipped = []
    if suite.configs:
        bases = []
        for base in suite.configs:
            missing = [name for name in base if name not in settings]
            if missing:
                skipped.append(f"{report.config_label(base)}: scene.bounce has no setting {', '.join(missing)} in this "
                               "build")
            elif not args.method or base["method"] == args.method:
                bases.append(base)
    else:
        methods = [args.method or suite.method]
        if suite.direct_baseline and "DIRECT" not in methods:
            methods.append("DIRECT")
        bases = [{"method": method} for method in methods]
    sets.update(parse_sets(args.set))
    names = list(sets)
    configs = [dict(base, **dict(zip(names, values))) for base in bases
               for values in itertools.product(*(sets[n] for n in names))]
    varying = {k for c in configs for k in c if k != "method" and len({str(d.get(k)) for d in configs}) > 1}
    return configs, [n for n in dict.fromkeys(k for c in configs for k in c) if n in varying], skipped


def jobs_for(scene, width, height, configs, args, suite, renders, errors):
    repeats = args.repeats or (1 if args.quick else suite.repeats)
    jobs = []
    for i, config in enumerate(configs):
        label = f"{scene.name} {width}x{height} " + " ".join(f"{k}={v}" for k, v in config.items())
        exr = renders / f"{scene.name}-{width}x{height}-bounce-{i:03d}.exr" if errors else None
        meta = {"role": "measure", "scene": scene.name, "label": label, "method": config["method"],
                "params": config}
        jobs.append(runner.bounce_job(width, height, config, repeats, exr, meta))
    cycles_samples = (args.cycles_samples and [int(v) for v in args.cycles_samples.split(",")]) or \
        (suite.quick_cycles_samples if args.quick else suite.cycles_samples)
    for samples in cycles_samples:
        exr = renders / f"{scene.name}-{width}x{height}-cycles-{samples:04d}.exr"
        meta = {"role": "measure", "scene": scene.name, "label": f"{scene.name} {width}x{height} Cycles {samples}",
                "method": "CYCLES", "params": {"samples": samples}}
        jobs.append(runner.cycles_job(width, height, samples, runner.CYCLES_SEED, args.cycles_device, exr, meta,
                                      bounces=suite.reference_bounces))
    return jobs


class Errors:
    """Loads each reference once and measures renders against it (and against the CPU model, if wanted).
    `references`: the Cycles references with 1 .. k bounces; renders are measured against the k-bounce one,
    and with k = 2 each bounce against its own part. With `by_bounces`, each render is measured against the
    bounces its method simulates instead (simulated_bounces), and its combined also against the k-bounce reference
    ('full_' columns)."""

    def __init__(self, references, cpu_references, by_bounces=False):
        self.references, self.cpu_references, self.loaded = references, cpu_references, {}
        self.by_bounces = by_bounces

    def paths(self, scene, width, height):
        return [str(r.path(scene, width, height)) for r in self.references]

    def reference(self, scene, width, height):
        return images.reference_from([self._load(p) for p in self.paths(scene, width, height)])

    def _load(self, path):
        if path not in self.loaded:
            self.loaded[path] = images.load(path)
        return self.loaded[path]

    def measure(self, scene, record):
        if not record.get("exr"):
            return {}
        image = images.load(record["exr"])
        reference = self.reference(scene, record["width"], record["height"])
        if not self.by_bounces:
            errors = images.compare(image, reference, "")
        else:
            bounces = simulated_bounces(record, len(self.references))
            target = images.up_to(reference, bounces)
            errors = images.compare(images.bounces_apart(image, bounces), target, "")
            errors.update(images.compare(image, reference, "full_", parts=("combined",)), oracle_bounces=bounces,
                          reference_exrs=self.paths(scene, record["width"], record["height"]))
            errors.update(images.bounces_error_shares(image, target, reference, images.geometry_mask(image, reference)))
        if self.cpu_references is not None:
            model = self._load(self.cpu_references.path(scene, record["width"], record["height"]))
            reference = images.against_cpu_model(image, model)
            if reference is not None:
                errors.update(images.compare(image, reference, "cpuref_"))
        return errors


def simulated_bounces(record, most):
    """The diffuse bounces a render simulates, at most `most`, as its frame said (BounceFrameInfo::bounces); a
    Cycles render the `most` of the references it is measured with. AUTO (a render with a plan) is measured
    against `most`: the bounces it leaves out count as its error."""
    if record.get("engine") == "CYCLES" or record.get("plan"):
        return most
    return min(int(record["bounces_simulated"]), most)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    suite = SUITES[args.suite]
    started = time.perf_counter()
    out = (args.out or runner.BUILD / "benchmark" / suite.name).resolve()
    for folder in ("renders", "logs") if not args.report_only else ():
        runner.clear(out / folder)
    runner.ensure_built()
    probe = runner.probe(out / "logs")
    log(f"Blender {probe['blender']}, GL {probe['gl']}")
    cache = runner.BUILD / "benchmark" / "scenes"
    scenes = plan_scenes(args, suite, cache)
    configs, swept, skipped = sweep(args, suite, probe.get("settings", {}))
    for sentence in skipped:
        log(f"skipped {sentence}")
    errors = suite.errors and not args.no_errors
    references = [runner.References(args.references or runner.BUILD / "benchmark" / "references", probe["blender"],
                                    args.reference_samples or (32 if args.quick else 1024), args.cycles_device,
                                    bounces) for bounces in range(1, suite.reference_bounces + 1)]
    use_cpu_model = errors and suite.cpu_reference and not args.no_cpu_reference and \
        "FLC" in {c["method"] for c in configs}
    cpu_references = runner.CpuReferences(
        references[0].folder, args.cpu_reference_points or (4096 if args.quick else 65536)) if use_cpu_model else None
    measure = Errors(references, cpu_references, by_bounces=suite.reference_per_method)

    if args.report_only:
        records = [json.loads(line) for line in (out / "records.jsonl").read_text().splitlines() if line.strip()]
    else:
        records = []
        for index, (scene, width, height) in enumerate(scenes if suite.script is None else (), 1):
            jobs = jobs_for(scene, width, height, configs, args, suite, out / "renders", errors or suite.images)
            if errors:
                jobs = [job for r in references for job in r.missing_jobs(scene, [(width, height)])] + jobs
            if cpu_references is not None:
                jobs = cpu_references.missing_jobs(scene, [(width, height)]) + jobs
            renders = sum(job.get("repeats", 1) for job in jobs)
            log(f"scene {index}/{len(scenes)}: {scene.name} at {width}x{height}, {renders} renders")
            scene_start = time.perf_counter()
            scene_records = runner.run_blender(scene, jobs, out / "logs")
            if cpu_references is not None:
                cpu_references.complete(out / "logs")
            for record in scene_records:
                if record.get("role") == "measure":
                    record.update(suite=suite.name, **measure.measure(scene, record) if errors else {})
                if record.get("role") in ("measure", "warm-up"):
                    records.append(record)
            log(f"scene {scene.name} done in {time.perf_counter() - scene_start:.1f} s")

        if suite.script is not None:
            config = {k: v for k, v in suite.script_config.items() if k != "quick"}
            config.update(suite.script_config.get("quick", {}) if args.quick else {})
            for scene, width, height in scenes:
                log(f"{scene.name} at {width}x{height}: {suite.summary}")
                # A record's own width and height (another image size it measured) win over the scene's.
                records += [dict({"width": width, "height": height}, **r, scene=scene.name, role="measure")
                            for r in runner.run_script(scene, runner.HERE / suite.script,
                                                       dict(config, width=width, height=height,
                                                            images=str(out / "renders")), out / "logs",
                                                       (width, height) if suite.gui else None)]

    with open(out / "records.jsonl", "w") as f:
        f.writelines(json.dumps(r) + "\n" for r in records)
    report.write_csv(out / "records.csv", records)
    title = (f"Bounce {suite.name}: {probe['gl'].split(' |')[0]}, {os.cpu_count()} CPU cores, "
             f"Blender {probe['blender']}" + (" (quick)" if args.quick else ""))
    ctx = Context(suite, out, swept, title, skipped)
    text = suite.report(ctx, records, report.stage_names(records))
    summary = ctx.summarise(records, ["scene", "engine", "method", "width", "height", *swept, "samples"])
    report.write_csv(out / "summary.csv", summary)
    elapsed = time.perf_counter() - started
    document = (f"## {suite.name}\n\n{suite.summary}. {title}; {elapsed:.0f} s in all.\n\n{text}\n")
    (out / f"{suite.name}.md").write_text(document)
    print(document)
    log(f"wrote {out}/records.csv, summary.csv, {suite.name}.md, {suite.name}.png ({elapsed:.0f} s)")


if __name__ == "__main__":
    main()
