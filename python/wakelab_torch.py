"""wakelab's detectors in PyTorch: load a `*.pytorch.safetensors` export with strict=True.

wakelab (Rust, burn) saves every trained detector twice: `NAME.safetensors` for wakelab and
`NAME.pytorch.safetensors` in PyTorch's layout (linear weights as [out, in], BatchNorm's
gamma/beta as weight/bias). This module defines the same networks (spec Tables 4.1-4.3) with the
same parameter names, so the export loads with `load_state_dict(strict=True)`:

    from wakelab_torch import load_detector, detector_input
    model, info = load_detector("S_unet.pytorch.safetensors")
    x = detector_input(sigma0_image, info["bands"][0])        # a 2-D numpy array
    p = model(torch.from_numpy(x)[None, None])                 # wake probability, shape [1]

Architectures: "base" (the image), "cls" (the image and a copy of its first band) and "unet"
(the image and the mask a U-Net of any width draws on it). A detector may read its window's
line sums instead of its pixels (`info["input_form"] == "line_sums"`, file format 3) and may pool
its last map to each channel's largest response (`info["head"] == "global_max"`, format 4), as
the shipped detectors in `models/` do; pass `info` to `detector_input` and it makes the input
the detector reads:

    model, info = load_detector("models/C_transfer_1280m.pytorch.safetensors")
    x = detector_input(window, "C", info)                      # 64 x 64 of linear sigma0 at 20 m
    p = model(torch.from_numpy(x)[None, None])                 # calibrated, as `wakelab detect`
    p = model.window_probability(window)                       # the same, input made from info

`detector_input` without `info` makes pixels: pass `info` (or use `window_probability`) for a
detector that reads line sums.

A detector whose file records a temperature (`wakelab.temperature`) returns its probabilities
scaled by it, as wakelab reports them. PyTorch, numpy and safetensors are the only
requirements; wakelab itself never needs Python.
"""
import numpy as np
import torch
from safetensors import safe_open
from safetensors.torch import load_file
from torch import nn
from torch.nn import functional as F

#: The input normalisation this module implements (wakelab's `INPUT_NORMALISATION`); a detector
#: file that records another is refused.
INPUT_NORMALISATION = (
    "robust-v1: radar sigma0 in dB, infrared brightness temperature; (v - median) / (1.4826 MAD)"
)
#: The detector file formats this module reads: 2 (pixels, Table 4.1's flatten), 3 (line sums)
#: and 4 (a head that pools the last map); wakelab's `FORMAT`, `LINE_SUMS_FORMAT`, `HEAD_FORMAT`.
FORMATS = ("wakelab-detector-2", "wakelab-detector-3", "wakelab-detector-4")
RADAR_BANDS = ("S", "C", "X")
INPUT_FORMS = ("pixels", "line_sums")
HEADS = ("flatten", "global_max")
#: Pixels beyond +-CLIP robust deviations are clipped before their line is summed (wakelab's
#: `line_sums::CLIP`).
CLIP = 3.0


class Classifier(nn.Module):
    """Table 4.1: three (conv 3x3, BatchNorm, ReLU, max-pool 2) stages of 10, 20 and 30 channels,
    then Linear 70 -> 30 -> 1 with no activation between them; returns logits, shape [batch].
    With head "global_max" each channel's largest response over the last map replaces the
    flatten (Linear 30 -> 70 -> 30 -> 1)."""

    def __init__(self, channels, size, head="flatten"):
        super().__init__()
        if head not in HEADS:
            raise ValueError(f"head {head!r}: one of {', '.join(HEADS)}")
        self.head = head
        self.conv1, self.norm1 = nn.Conv2d(channels, 10, 3), nn.BatchNorm2d(10)
        self.conv2, self.norm2 = nn.Conv2d(10, 20, 3), nn.BatchNorm2d(20)
        self.conv3, self.norm3 = nn.Conv2d(20, 30, 3), nn.BatchNorm2d(30)
        side = size
        for _ in range(3):
            side = (side - 2) // 2
        self.linear1 = nn.Linear(30 if head == "global_max" else 30 * side * side, 70)
        self.linear2 = nn.Linear(70, 30)
        self.linear3 = nn.Linear(30, 1)

    def forward(self, x):
        for conv, norm in ((self.conv1, self.norm1), (self.conv2, self.norm2), (self.conv3, self.norm3)):
            x = F.max_pool2d(F.relu(norm(conv(x))), 2)
        x = x.flatten(2).amax(2) if self.head == "global_max" else x.flatten(1)
        return self.linear3(self.linear2(self.linear1(x))).flatten()


class DoubleConv(nn.Module):
    """Table 4.3: conv 3x3 (padding 1), ReLU, conv 3x3 (padding 1), ReLU."""

    def __init__(self, i, o):
        super().__init__()
        self.first = nn.Conv2d(i, o, 3, padding=1)
        self.second = nn.Conv2d(o, o, 3, padding=1)

    def forward(self, x):
        return F.relu(self.second(F.relu(self.first(x))))


class UNet(nn.Module):
    """Table 4.2 at first-level width w (w-2w-4w-8w; the paper's is 64): max-pool down, bilinear
    (align_corners) up with skip connections; returns per-pixel logits [batch, 1, h, w]."""

    def __init__(self, channels, width=64):
        super().__init__()
        w = width
        self.down0, self.down1 = DoubleConv(channels, w), DoubleConv(w, 2 * w)
        self.down2, self.bottom = DoubleConv(2 * w, 4 * w), DoubleConv(4 * w, 8 * w)
        self.up2, self.up1 = DoubleConv(12 * w, 4 * w), DoubleConv(6 * w, 2 * w)
        self.up0 = DoubleConv(3 * w, w)
        self.output = nn.Conv2d(w, 1, 1)

    def forward(self, x):
        def up(t):
            return F.interpolate(t, scale_factor=2, mode="bilinear", align_corners=True)

        l0 = self.down0(x)
        l1 = self.down1(F.max_pool2d(l0, 2))
        l2 = self.down2(F.max_pool2d(l1, 2))
        x = self.bottom(F.max_pool2d(l2, 2))
        x = self.up2(torch.cat([up(x), l2], 1))
        x = self.up1(torch.cat([up(x), l1], 1))
        x = self.up0(torch.cat([up(x), l0], 1))
        return self.output(x)


class Detector(nn.Module):
    """A wakelab detector: its classifier and, for "unet", the U-Net whose mask it reads.
    `forward` takes images [batch, bands, n, n] made by `detector_input` and returns the wake
    probability per image, scaled by `temperature` (wakelab's `calibration::scaled`: the sigmoid
    of the logit over the temperature)."""

    def __init__(self, architecture, bands, size, unet_width=64, head="flatten", temperature=1.0):
        super().__init__()
        if architecture not in ("base", "cls", "unet"):
            raise ValueError(f"architecture {architecture!r}: one of base, cls, unet")
        if not temperature > 0.0:
            raise ValueError(f"temperature {temperature!r}: must be a positive number")
        self.architecture = architecture
        self.temperature = float(temperature)
        #: set by `load_detector` from the file: what `window_probability` makes of a window
        self.info = None
        extra = 0 if architecture == "base" else 1
        self.classifier = Classifier(bands + extra, size, head)
        self.segmenter = UNet(bands, unet_width) if architecture == "unet" else None

    def mask(self, images):
        """The U-Net's wake mask (per-pixel probability) of a "unet" detector."""
        return torch.sigmoid(self.segmenter(images))

    def forward(self, images):
        if self.architecture == "cls":
            images = torch.cat([images, images[:, :1]], 1)
        elif self.architecture == "unet":
            images = torch.cat([images, self.mask(images)], 1)
        return torch.sigmoid(self.classifier(images) / self.temperature)

    def window_probability(self, window):
        """The wake probability of one window (a 2-D numpy array of the detector's band, radar
        sigma0 linear), its input made as the file says (`detector_input` with this detector's
        info: its line sums where it reads them), so that no caller can hand a line-sum
        detector pixels. A single-band detector loaded by `load_detector` only."""
        if self.info is None or len(self.info["bands"]) != 1:
            raise ValueError("window_probability needs a single-band detector loaded by load_detector")
        x = detector_input(window, self.info["bands"][0], self.info)
        with torch.no_grad():
            return float(self(torch.from_numpy(x)[None, None])[0])


def read_info(path):
    """The `wakelab.*` metadata of a detector file, checked: format, input normalisation, input
    form and head. A file in wakelab's own layout is refused: this module reads its export."""
    with safe_open(path, framework="pt") as f:
        meta = f.metadata() or {}
    if meta.get("wakelab.format") not in FORMATS:
        raise ValueError(f"{path}: format {meta.get('wakelab.format')!r}, this module reads {', '.join(FORMATS)}")
    if meta.get("wakelab.normalisation") != INPUT_NORMALISATION:
        raise ValueError(f"{path}: inputs normalised as {meta.get('wakelab.normalisation')!r}")
    if meta.get("wakelab.layout", "pytorch") != "pytorch":
        raise ValueError(f"{path}: wakelab's own layout; load its PyTorch export (NAME.pytorch.safetensors)")
    form = meta.get("wakelab.input_form", "pixels")
    head = meta.get("wakelab.head", "flatten")
    if form not in INPUT_FORMS:
        raise ValueError(f"{path}: wakelab.input_form {form!r}, one of {', '.join(INPUT_FORMS)}")
    if head not in HEADS:
        raise ValueError(f"{path}: wakelab.head {head!r}, one of {', '.join(HEADS)}")
    spacing = meta.get("wakelab.pixel_spacing")
    return {
        "architecture": meta["wakelab.architecture"],
        "bands": meta["wakelab.bands"].split(","),
        "input_size": int(meta["wakelab.input_size"]),
        "threshold": float(meta["wakelab.threshold"]),
        "unet_width": int(meta.get("wakelab.unet_width", 64)),
        "input_form": form,
        "head": head,
        "temperature": float(meta.get("wakelab.temperature", 1.0)),
        "pixel_spacing": None if spacing is None else float(spacing),
    }


def load_detector(path):
    """A detector from its PyTorch export, loaded with strict=True, in eval mode; and its info."""
    info = read_info(path)
    model = Detector(
        info["architecture"],
        len(info["bands"]),
        info["input_size"],
        info["unet_width"],
        info["head"],
        info["temperature"],
    )
    # BatchNorm's num_batches_tracked is not in the file: PyTorch fills it in for a state dict
    # without version metadata, so strict loading still checks every other name and shape
    model.load_state_dict(load_file(path), strict=True)
    model.info = info
    return model.eval(), info


def upper_median(values):
    """The median as wakelab takes it: the upper one of an even count."""
    v = np.sort(values.ravel())
    return v[len(v) // 2]


def detector_input(image, band, info=None):
    """wakelab's input for one band's image (`INPUT_NORMALISATION`): radar sigma0 (linear) in
    dB, then (v - median) / (1.4826 MAD); where the MAD is 0 the mean absolute deviation stands
    in, and a constant image becomes zeros. With the `info` of a detector that reads line sums,
    their plane (`line_sums`) instead. Returns float32 [n, n]."""
    normalised = robust_normalise(image, band)
    if info is not None and info.get("input_form", "pixels") == "line_sums":
        return line_sums(normalised)
    return normalised


def robust_normalise(image, band):
    """(v - median) / (1.4826 MAD) of the image, radar bands in dB first (see `detector_input`)."""
    v = np.asarray(image, dtype=np.float64)
    if band in RADAR_BANDS:
        v = 10.0 * np.log10(np.maximum(v, 1e-30))
    v = v.astype(np.float32)
    centre = upper_median(v)
    deviations = np.abs(v - centre)
    scale = 1.4826 * float(upper_median(deviations))
    if scale <= 0.0:
        scale = float(deviations.mean())
    if scale <= 0.0:
        return np.zeros_like(v, dtype=np.float32)
    return ((v - centre) / scale).astype(np.float32)


def line_sums(window):
    """A square window's line sums (wakelab's `line_sums`; its Radon transform, Radon 1917): row a
    is the direction theta = 180 a / n degrees of the lines' normal, column b the lines
    x cos theta + y sin theta in [b - n/2, b + 1 - n/2) pixels from the window's centre; each value
    is the sum of the window's pixels on the line, clipped at +-CLIP (non-finite as 0), over the
    square root of their count. The bins are computed in float32 as wakelab computes them."""
    v = np.asarray(window, dtype=np.float32)
    n = v.shape[0]
    if v.shape != (n, n):
        raise ValueError(f"a square window, not {v.shape}")
    values = np.where(np.isfinite(v), np.clip(v, -CLIP, CLIP), 0.0).astype(np.float64).ravel()
    centre = np.float32(0.5 * n)
    out = np.zeros((n, n), dtype=np.float32)
    rows = np.arange(n, dtype=np.float32)
    cols = np.arange(n, dtype=np.float32)
    for a in range(n):
        theta = np.float32(np.pi) * np.float32(a) / np.float32(n)
        cos = np.float32(np.cos(np.float64(theta)))
        sin = np.float32(np.sin(np.float64(theta)))
        start = (np.float32(0.5) - centre) * cos + (rows + np.float32(0.5) - centre) * sin + centre
        bins = np.floor(start[:, None] + cols[None, :] * cos).ravel()
        inside = (bins >= 0) & (bins < n)
        b = bins[inside].astype(np.int64)
        sums = np.bincount(b, weights=values[inside], minlength=n)
        counts = np.bincount(b, minlength=n).astype(np.float32)
        roots = np.sqrt(counts)
        out[a] = np.where(roots > 0, sums / np.where(roots > 0, roots, 1.0), 0.0)
    return out
