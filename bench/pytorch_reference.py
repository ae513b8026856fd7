"""PyTorch reference for wakelab's learning benchmark (its speed beside a reference).

The same networks as wakelab-learn (spec Tables 4.1-4.3), the same recipes (SGD lr 1e-3, L2 0.1 on
BCE for "base"; Adam lr 1e-4, weight decay 1e-4 on 0.7 BCE + 0.3 log-Dice for the U-Net), timed
per training step on the CPU with 2 threads. Prints one JSON object: images per second.

Run through bench/learning_vs_pytorch.sh, which installs torch into a throwaway venv; torch is
never a dependency of wakelab.
"""
import json
import sys
import time

import torch
from torch import nn

torch.set_num_threads(int(sys.argv[1]) if len(sys.argv) > 1 else 2)
torch.manual_seed(0)


class Classifier(nn.Module):
    def __init__(self, channels, size):
        super().__init__()
        layers = []
        for i, o in [(channels, 10), (10, 20), (20, 30)]:
            layers += [nn.Conv2d(i, o, 3), nn.BatchNorm2d(o), nn.ReLU(inplace=True), nn.MaxPool2d(2)]
        self.features = nn.Sequential(*layers)
        side = size
        for _ in range(3):
            side = (side - 2) // 2
        self.head = nn.Sequential(nn.Linear(30 * side * side, 70), nn.Linear(70, 30), nn.Linear(30, 1))

    def forward(self, x):
        return self.head(self.features(x).flatten(1)).flatten()


def double_conv(i, o):
    return nn.Sequential(nn.Conv2d(i, o, 3, padding=1), nn.ReLU(inplace=True), nn.Conv2d(o, o, 3, padding=1), nn.ReLU(inplace=True))


class UNet(nn.Module):
    def __init__(self, channels):
        super().__init__()
        self.d0, self.d1, self.d2, self.b = double_conv(channels, 64), double_conv(64, 128), double_conv(128, 256), double_conv(256, 512)
        self.u2, self.u1, self.u0 = double_conv(768, 256), double_conv(384, 128), double_conv(192, 64)
        self.out = nn.Conv2d(64, 1, 1)
        self.pool = nn.MaxPool2d(2)
        self.up = nn.Upsample(scale_factor=2, mode="bilinear", align_corners=True)

    def forward(self, x):
        l0 = self.d0(x)
        l1 = self.d1(self.pool(l0))
        l2 = self.d2(self.pool(l1))
        x = self.b(self.pool(l2))
        x = self.u2(torch.cat([self.up(x), l2], 1))
        x = self.u1(torch.cat([self.up(x), l1], 1))
        x = self.u0(torch.cat([self.up(x), l0], 1))
        return self.out(x)


def unet_loss(logits, masks):
    bce = nn.functional.binary_cross_entropy_with_logits(logits, masks)
    p = torch.sigmoid(logits).flatten(1)
    y = masks.flatten(1)
    dice = (2 * (p * y).sum(1) + 1) / (p.sum(1) + y.sum(1) + 1)
    return 0.7 * bce - 0.3 * torch.log(dice).mean()


def time_steps(step, warmup, steps):
    for _ in range(warmup):
        step()
    start = time.perf_counter()
    for _ in range(steps):
        step()
    return (time.perf_counter() - start) / steps


def scan(side, window=32, stride=32, batch=256):
    """`wakelab detect`'s work on a side x side single-band image with "base" (window 32): every
    window normalised by its median and 1.4826 MAD (the upper median, as wakelab), scored in
    batches, the wake probabilities averaged over the stride cells. Seconds for the whole scan."""
    model = Classifier(1, window).eval()
    image = torch.randn(side, side)
    start = time.perf_counter()
    with torch.no_grad():
        windows = image.unfold(0, window, stride).unfold(1, window, stride)
        rows, cols = windows.shape[:2]
        windows = windows.reshape(-1, window * window)
        k = window * window // 2 + 1
        probabilities = []
        for chunk in windows.split(batch):
            centre = chunk.kthvalue(k, dim=1, keepdim=True).values
            mad = (chunk - centre).abs().kthvalue(k, dim=1, keepdim=True).values * 1.4826
            x = ((chunk - centre) / mad.clamp_min(1e-12)).reshape(-1, 1, window, window)
            probabilities.append(torch.sigmoid(model(x)))
        cells = torch.cat(probabilities).reshape(rows, cols)
    seconds = time.perf_counter() - start
    assert cells.shape == (side // stride, side // stride)
    return seconds


def scan_product(rows, cols, window=32, stride=16, batch=256, band_rows=2048):
    """The same work as `scan` on a rows x cols product at `stride` (detect's default: half the
    window), a band of window rows at a time so that memory holds one band's windows (PyTorch's
    unfold of a whole Sentinel-1 product at stride 16 would copy 7 GB). Seconds for the scan."""
    model = Classifier(1, window).eval()
    generator = torch.Generator().manual_seed(0)
    image = torch.randn(rows, cols, generator=generator)
    k = window * window // 2 + 1
    start = time.perf_counter()
    with torch.no_grad():
        origins = list(range(0, rows - window + 1, stride))
        per_band = max(1, band_rows // stride)
        for b in range(0, len(origins), per_band):
            first, last = origins[b], origins[min(b + per_band, len(origins)) - 1]
            band = image[first:last + window]
            windows = band.unfold(0, window, stride).unfold(1, window, stride).reshape(-1, window * window)
            for chunk in windows.split(batch):
                centre = chunk.kthvalue(k, dim=1, keepdim=True).values
                mad = (chunk - centre).abs().kthvalue(k, dim=1, keepdim=True).values * 1.4826
                x = ((chunk - centre) / mad.clamp_min(1e-12)).reshape(-1, 1, window, window)
                torch.sigmoid(model(x))
    return time.perf_counter() - start


def main():
    if len(sys.argv) > 2 and sys.argv[2] == "product":
        rows, cols = int(sys.argv[3]), int(sys.argv[4])
        seconds = scan_product(rows, cols)
        print(json.dumps({"torch": torch.__version__, "threads": torch.get_num_threads(), "rows": rows, "cols": cols,
                          "seconds": seconds, "megapixels_per_second": rows * cols / seconds / 1e6}))
        return
    results = {"torch": torch.__version__, "threads": torch.get_num_threads()}
    # PyTorch at its faster of two batch sizes
    seconds, batch = min((scan(8192, batch=b), b) for b in (64, 256))
    results["scan_8192_base"] = {"seconds": seconds, "batch": batch, "megapixels_per_second": 8192 * 8192 / seconds / 1e6}
    # "base" at 256 x 256, batch 8
    model = Classifier(1, 256)
    opt = torch.optim.SGD(model.parameters(), lr=1e-3, weight_decay=0.1)
    x = torch.randn(8, 1, 256, 256)
    y = torch.tensor([1.0, 0.0] * 4)

    def base_step():
        opt.zero_grad()
        loss = nn.functional.binary_cross_entropy_with_logits(model(x), y)
        loss.backward()
        opt.step()

    t = time_steps(base_step, 3, 20)
    results["base_256_batch8"] = {"seconds_per_step": t, "images_per_second": 8 / t}
    # U-Net at 128 x 128, batch 4
    unet = UNet(1)
    opt = torch.optim.Adam(unet.parameters(), lr=1e-4, weight_decay=1e-4)
    x = torch.randn(4, 1, 128, 128)
    m = (torch.rand(4, 1, 128, 128) > 0.9).float()

    def unet_step():
        opt.zero_grad()
        loss = unet_loss(unet(x), m)
        loss.backward()
        opt.step()

    t = time_steps(unet_step, 2, 8)
    results["unet_128_batch4"] = {"seconds_per_step": t, "images_per_second": 4 / t}
    print(json.dumps(results))


if __name__ == "__main__":
    main()
