"""EXR reading and the error metrics of scripts/benchmark (host Python: numpy, OpenImageIO).

What is compared (DESIGN.md, "Cycles as an oracle", with as many diffuse bounces as the method simulates):
  combined: Bounce's Combined  vs  Cycles' DiffCol * (DiffDir + DiffInd) + Emit
  indirect: Bounce's Indirect  vs  Cycles' DiffCol * DiffInd       (when Bounce writes an Indirect pass)
and, for two-bounce methods, each bounce alone (with_bounces: the one- and two-bounce references together):
  first:    Indirect - Second Bounce  vs  DiffCol * DiffInd(k=1)
  second:   Second Bounce             vs  DiffCol * (DiffInd(k=2) - DiffInd(k=1))
and against the CPU model reference (runner.CpuReferences), columns cpuref_*:
  indirect: the render's Indirect  vs  its own albedo (Albedo, or Cycles' DiffCol) * the model's white-receiver
            radiance, so texture detail is the render's and only the light differs
Errors, over the pixels where the reference sees geometry (its alpha > 0.5; the world is black) and the three
colour channels, x the image and r the reference:
  relative RMSE = sqrt(mean((x - r)^2)) / sqrt(mean(r^2))
  relative MAE  = mean(|x - r|) / mean(|r|)
"""
import numpy as np
import OpenImageIO as oiio

METRIC_TEXT = ("relative RMSE = sqrt(mean((x - r)^2)) / sqrt(mean(r^2)), relative MAE = mean(|x - r|) / mean(|r|), "
               "over the RGB values of the pixels where the reference sees geometry (alpha > 0.5)")

_CHANNEL_ORDER = "RGBAXYZVW"


def read_passes(path):
    """{pass name: (height, width, channels) float32} from an EXR. Multilayer channels are named
    'Layer.Pass.C'; a plain RGB(A) EXR comes back as the single pass 'Combined'."""
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise RuntimeError(f"cannot read {path}: {oiio.geterror()}")
    try:
        spec = image.spec()
        pixels = np.asarray(image.read_image(0, 0, 0, spec.nchannels, "float"), dtype=np.float32)
    finally:
        image.close()
    pixels = pixels.reshape(spec.height, spec.width, spec.nchannels)
    groups = {}
    for index, name in enumerate(spec.channelnames):
        parts = name.split(".")
        pass_name = parts[-2] if len(parts) >= 2 else "Combined"
        groups.setdefault(pass_name, []).append((parts[-1], index))
    passes = {}
    for pass_name, channels in groups.items():
        channels.sort(key=lambda c: _CHANNEL_ORDER.find(c[0]) if c[0] in _CHANNEL_ORDER else 99)
        passes[pass_name] = np.nan_to_num(pixels[:, :, [index for _, index in channels]])
    return passes


def _rgb(passes, name):
    return passes[name][:, :, :3]


def components(passes):
    """{'combined', 'indirect' (when available), 'alpha'} of a Bounce or Cycles-oracle render."""
    out = {}
    if "DiffCol" in passes:
        colour = _rgb(passes, "DiffCol")
        emission = _rgb(passes, "Emit") if "Emit" in passes else 0.0
        out["combined"] = colour * (_rgb(passes, "DiffDir") + _rgb(passes, "DiffInd")) + emission
        out["indirect"] = colour * _rgb(passes, "DiffInd")
        out["albedo"] = colour
    else:
        out["combined"] = _rgb(passes, "Combined")
        if "Indirect" in passes:
            out["indirect"] = _rgb(passes, "Indirect")
        if "Albedo" in passes:
            out["albedo"] = _rgb(passes, "Albedo")
        if "Second Bounce" in passes and "Indirect" in passes:
            out["second"] = _rgb(passes, "Second Bounce")
            out["first"] = out["indirect"] - out["second"]
    combined = passes.get("Combined")
    if combined is not None and combined.shape[2] >= 4:
        out["alpha"] = combined[:, :, 3]
    return out


def load(path):
    return components(read_passes(path))


def against_cpu_model(image, model):
    """The reference an image's indirect light is compared with: the CPU model's white-receiver radiance (a
    plain RGBA EXR, loaded by load()) times the image's own albedo. None when the image has no albedo."""
    if "albedo" not in image:
        return None
    return {"indirect": model["combined"] * image["albedo"], "alpha": model["alpha"]}


def with_bounces(two_bounce, one_bounce):
    """A two-bounce Cycles reference with each bounce apart ('first', 'second'), from the one-bounce render."""
    out = dict(two_bounce)
    out["first"] = one_bounce["indirect"]
    out["second"] = two_bounce["indirect"] - one_bounce["indirect"]
    return out


def relative_errors(image, reference, mask):
    """(relative RMSE, relative MAE) of `image` against `reference` over the pixels of `mask`."""
    if image.shape != reference.shape:
        raise ValueError(f"image {image.shape[1]}x{image.shape[0]} and reference "
                         f"{reference.shape[1]}x{reference.shape[0]} differ in size")
    x, r = image[mask].astype(np.float64), reference[mask].astype(np.float64)
    if r.size == 0:
        return float("nan"), float("nan")
    d = x - r
    rms_ref = np.sqrt(np.mean(r * r))
    mean_ref = np.mean(np.abs(r))
    return (float(np.sqrt(np.mean(d * d)) / rms_ref) if rms_ref > 0 else float("nan"),
            float(np.mean(np.abs(d)) / mean_ref) if mean_ref > 0 else float("nan"))


def compare(image, reference, prefix):
    """Errors of a loaded render against a loaded reference, as {'<prefix>combined_rel_rmse': ...}.
    Background pixels come from the reference's alpha, else from the image's."""
    alpha = reference.get("alpha", image.get("alpha"))
    mask = alpha > 0.5 if alpha is not None else np.ones(image["combined"].shape[:2], dtype=bool)
    errors = {}
    for part in ("combined", "indirect", "first", "second"):
        if part in image and part in reference:
            rmse, mae = relative_errors(image[part], reference[part], mask)
            errors[f"{prefix}{part}_rel_rmse"] = rmse
            errors[f"{prefix}{part}_rel_mae"] = mae
    return errors
