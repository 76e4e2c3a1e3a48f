"""EXR reading and the error metrics of scripts/benchmark (host Python: numpy, OpenImageIO).

What is compared (DESIGN.md, "Cycles as an oracle", with as many diffuse bounces as the method simulates):
  combined: Bounce's Combined  vs  Cycles' DiffCol * (DiffDir + DiffInd) + Emit
  direct:   Bounce's Direct    vs  Cycles' DiffCol * DiffDir
  indirect: Bounce's Indirect  vs  Cycles' DiffCol * DiffInd       (when Bounce writes an Indirect pass)
and, for two-bounce methods, each bounce alone (with_bounces: the one- and two-bounce references together):
  first:    Indirect - Second Bounce  vs  DiffCol * DiffInd(k=1)
  second:   Second Bounce             vs  DiffCol * (DiffInd(k=2) - DiffInd(k=1))
up_to() cuts such a reference down to the bounces one method simulates (0: direct light and emission only).
and against the CPU model reference (runner.CpuReferences), columns cpuref_*:
  indirect: the render's Indirect  vs  its own albedo (Albedo, or Cycles' DiffCol) * the model's white-receiver
            radiance, so texture detail is the render's and only the light differs
Errors, over the pixels where the reference sees geometry (its alpha > 0.5; the world is black) and the three
colour channels, x the image and r the reference:
  relative RMSE = sqrt(mean((x - r)^2)) / sqrt(mean(r^2))
  relative MAE  = mean(|x - r|) / mean(|r|)
  relMSE        = mean((x - r)^2 / (r^2 + 0.01)), per pixel and after a 4x4 box downsample of both images (so
                  pixel filters and sub-pixel shadow-edge shifts do not dominate)
  ratio         = mean(x) / mean(r), over the whole image and over its left, middle and right thirds (columns):
                  bias that relMSE's + 0.01 hides in dark indirect light (inf where only the reference is black,
                  below BLACK_LEVEL)
"""
import numpy as np
import OpenImageIO as oiio

METRIC_TEXT = ("relative RMSE = sqrt(mean((x - r)^2)) / sqrt(mean(r^2)), relative MAE = mean(|x - r|) / mean(|r|), "
               "over the RGB values of the pixels where the reference sees geometry (alpha > 0.5)")
THIRDS = ("left", "middle", "right")
DOWNSAMPLE = 4  # the box filter of the downsampled relMSE, in pixels
# Mean radiance that counts as black in the ratio of means: under half a code value of an 8-bit sRGB image. Stray
# light (a pixel filter spreading a sunlit patch, Cycles' rare paths through a wall's edge) stays below it.
BLACK_LEVEL = 1e-4

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
        out["direct"] = colour * _rgb(passes, "DiffDir")
        out["indirect"] = colour * _rgb(passes, "DiffInd")
        out["emission"] = emission + np.zeros_like(colour)
        out["albedo"] = colour
    else:
        out["combined"] = _rgb(passes, "Combined")
        if "Direct" in passes:
            out["direct"] = _rgb(passes, "Direct")
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
    """A two-bounce Cycles reference with each bounce apart ('first', 'second'), from the one-bounce render, whose
    direct light stands for both."""
    out = dict(two_bounce)
    out["direct"] = one_bounce["direct"]
    out["first"] = one_bounce["indirect"]
    out["second"] = two_bounce["indirect"] - one_bounce["indirect"]
    return out


def reference_from(loaded):
    """The reference of loaded Cycles references with 1 .. k bounces (each bounce apart when k = 2)."""
    return loaded[-1] if len(loaded) == 1 else with_bounces(loaded[-1], loaded[0])


def bounces_apart(image, bounces):
    """A Bounce render's components with its first bounce apart when it simulates `bounces`: a one-bounce
    render's Indirect is its first bounce (Bounce writes the first bounce apart only beside a Second Bounce)."""
    if bounces == 1 and "indirect" in image and "first" not in image:
        return dict(image, first=image["indirect"])
    return image


def up_to(reference, bounces):
    """A reference of with_bounces cut down to `bounces` diffuse bounces (0, 1 or 2): what a method that simulates
    that many converges to. Its combined is the direct light and emission plus the bounces kept."""
    if bounces >= 2 or "first" not in reference:
        return reference
    out = {k: v for k, v in reference.items() if k != "second"}
    out["indirect"] = reference["first"] if bounces == 1 else np.zeros_like(reference["first"])
    out["combined"] = reference["direct"] + reference["emission"] + out["indirect"]
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


def relative_mse(image, reference, mask):
    """mean((x - r)^2 / (r^2 + 0.01)) over the RGB values of the pixels of `mask`."""
    x, r = image[mask].astype(np.float64), reference[mask].astype(np.float64)
    return float(np.mean((x - r) ** 2 / (r * r + 0.01))) if r.size else float("nan")


def bounces_error_shares(image, target, reference, mask):
    """The bounces' part of a render's combined relMSE against `reference` (Cycles with every bounce): the mean of
    (x - t)^2 / (r^2 + 0.01) for x its indirect light, t the reference's indirect light at the render's own bounce
    count (`target`) and r the reference's combined; and the same with x = 0, the relMSE that leaving the bounces
    out would cost (the scene analysis's error weight of them). Their ratio, once the noise is taken out, is the
    method's bias class (native/src/auto_plan.h)."""
    if "indirect" not in image or "indirect" not in target or not mask.any():
        return {}
    x, t = image["indirect"][mask].astype(np.float64), target["indirect"][mask].astype(np.float64)
    r = reference["combined"][mask].astype(np.float64)
    weight = 1.0 / (r * r + 0.01)
    return {"bounces_error_share": float(np.mean((x - t) ** 2 * weight)),
            "bounces_weight": float(np.mean(t * t * weight))}


def box_downsample(image, factor=DOWNSAMPLE):
    """The mean of each factor x factor block (rows and columns past the last whole block are dropped)."""
    h, w = image.shape[0] // factor * factor, image.shape[1] // factor * factor
    blocks = image[:h, :w].reshape(h // factor, factor, w // factor, factor, *image.shape[2:])
    return blocks.mean(axis=(1, 3))


def mean_ratios(image, reference, mask):
    """mean(x) / mean(r) over `mask`, then over each third of the columns; also both means. A mean below
    BLACK_LEVEL, or below a thousandth of the reference's mean over the whole image, is black: where the reference
    is black the ratio is inf, or nan where the image is black too."""
    def means(columns):
        return tuple(float(np.mean(v[:, columns][mask[:, columns]])) if mask[:, columns].any() else float("nan")
                     for v in (image, reference))

    mean_x, mean_r = means(slice(None))
    black = max(BLACK_LEVEL, 1e-3 * mean_r)

    def ratio(x, r):
        return x / r if r > black else float("inf") if x > black else float("nan")

    out = {"mean": mean_x, "reference_mean": mean_r, "ratio": ratio(mean_x, mean_r)}
    for name, columns in zip(THIRDS, np.array_split(np.arange(image.shape[1]), 3)):
        out[f"ratio_{name}"] = ratio(*means(columns))
    return out


def geometry_mask(image, reference):
    """The pixels that see geometry: from the reference's alpha, else from the image's, else all."""
    alpha = reference.get("alpha", image.get("alpha"))
    return alpha > 0.5 if alpha is not None else np.ones(image["combined"].shape[:2], dtype=bool)


def compare(image, reference, prefix, parts=("combined", "direct", "indirect", "first", "second")):
    """Errors of a loaded render against a loaded reference, as {'<prefix>combined_rel_rmse': ...}: per part,
    relative RMSE and MAE, relMSE at full size and downsampled ('_rel_mse_4x4'), the ratio of means (overall and
    per third) and both means, over geometry_mask's pixels."""
    mask = geometry_mask(image, reference)
    # A downsampled pixel counts when most of its block sees geometry; background is black in both images.
    small_mask = box_downsample(mask.astype(np.float32)) > 0.5
    errors = {}
    for part in parts:
        if part in image and part in reference:
            x, r = image[part], reference[part]
            rmse, mae = relative_errors(x, r, mask)
            errors[f"{prefix}{part}_rel_rmse"] = rmse
            errors[f"{prefix}{part}_rel_mae"] = mae
            errors[f"{prefix}{part}_rel_mse"] = relative_mse(x, r, mask)
            errors[f"{prefix}{part}_rel_mse_{DOWNSAMPLE}x{DOWNSAMPLE}"] = relative_mse(
                box_downsample(x), box_downsample(r), small_mask)
            errors.update({f"{prefix}{part}_{k}": v for k, v in mean_ratios(x, r, mask).items()})
    return errors
