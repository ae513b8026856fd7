#!/usr/bin/env python3
"""Write the three real wake-free images of docs/results.md ("Three real images without a wake")
as the transfer study's `--real` reads them: je24.npy, hs.npy and kp.png, each with its
NAME.geojson (no wake drawn, its scale and pixel spacing in "wakelab").

usage: wake_free_images.py OUT [--mirrors DIR]

  je24  AIRCentre/JuliaEO24@4016a10, the VV measurement of
        notebooks/VesselDetection/data/S1A_..._EA25_test.SAFE (a 1000 x 1000 Sentinel-1 IW GRDH
        subset at 10 m): sigma0 = DN^2 / 598.9^2, 598.9 the median sigmaNought of the
        calibration annotation (its sea median comes out at -23.5 dB), linear, 10 m.
  hs    harshal306/ShipDetectionBCFAR_SARImagery@1119fe4, Package/DAS/tests/Input.tif, an
        amplitude of unknown gain: (A / median A)^2 x 0.01, so the sea's median is -20 dB;
        linear, about 10 m.
  kp    kira-parth/sar-ship-detection-fpga@f3b4a82, Data/P0119_2400_3200_6000_6800.png, an HRSID
        chip kept whole (grey stored as RGB, which detect reads as one band); display scale, its
        unstated spacing taken as 3 m.

DIR (default /work/.mirror) holds the three repositories as OWNER+NAME/repo (bare repositories,
as `fetch` writes them) or OWNER+NAME; files are read with `git show COMMIT:PATH`. Needs numpy
and GDAL's Python bindings (python3-gdal). Prints each output's name and sha256.
"""
import argparse
import hashlib
import json
import os
import subprocess
import tempfile

import numpy as np
from osgeo import gdal

SAFE = ('notebooks/VesselDetection/data/S1A_IW_GRDH_1SDV_20220612T173329_20220612T173354_043633_05359A_EA25_test.SAFE/'
        'measurement/s1a-iw-grd-vv-20220612t173329-20220612t173354-043633-05359a-002.tiff')
SOURCES = {
    'je24': ('AIRCentre+JuliaEO24', '4016a10', SAFE),
    'hs': ('harshal306+ShipDetectionBCFAR_SARImagery', '1119fe4', 'Package/DAS/tests/Input.tif'),
    'kp': ('kira-parth+sar-ship-detection-fpga', 'f3b4a82', 'Data/P0119_2400_3200_6000_6800.png'),
}
SIGMA_NOUGHT = 598.9


def git_show(mirrors, repo, commit, path):
    for where in (os.path.join(mirrors, repo, 'repo'), os.path.join(mirrors, repo)):
        if os.path.isdir(where):
            git_dir = os.path.join(where, '.git') if os.path.isdir(os.path.join(where, '.git')) else where
            return subprocess.run(['git', f'--git-dir={git_dir}', 'show', f'{commit}:{path}'],
                                  check=True, capture_output=True).stdout
    raise SystemExit(f'{repo}: not in {mirrors} (fetch github:{repo.replace("+", "/")} first)')


def read_band(data, suffix):
    with tempfile.NamedTemporaryFile(suffix=suffix) as f:
        f.write(data)
        f.flush()
        return gdal.Open(f.name).ReadAsArray().astype(np.float64)


def drawing(scale, spacing, note):
    return {'type': 'FeatureCollection', 'wakelab': {'coordinates': 'pixel', 'pixel_spacing_m': spacing, 'scale': scale},
            'notes': note + '; no_wake', 'features': []}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('out')
    parser.add_argument('--mirrors', default='/work/.mirror')
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    written = {}
    for name, (repo, commit, path) in SOURCES.items():
        data = git_show(args.mirrors, repo, commit, path)
        source = f"SOURCE {repo.replace('+', '/')}@{commit}:{path}"
        if name == 'je24':
            sigma0 = read_band(data, '.tiff') ** 2 / SIGMA_NOUGHT ** 2
            np.save(os.path.join(args.out, 'je24.npy'), sigma0.astype(np.float32))
            meta = drawing('linear', 10, source + ', DN^2 / 598.9^2')
            written['je24.npy'] = f'sea median {10 * np.log10(np.median(sigma0)):.2f} dB'
        elif name == 'hs':
            amplitude = read_band(data, '.tif')
            np.save(os.path.join(args.out, 'hs.npy'), ((amplitude / np.nanmedian(amplitude)) ** 2 * 0.01).astype(np.float32))
            meta = drawing('linear', 10, source + ', (A / median A)^2 x 0.01')
            written['hs.npy'] = ''
        else:
            with open(os.path.join(args.out, 'kp.png'), 'wb') as f:
                f.write(data)
            meta = drawing('display', 3, source)
            written['kp.png'] = ''
        with open(os.path.join(args.out, name + '.geojson'), 'w') as f:
            json.dump(meta, f, indent=1)
    for file, note in written.items():
        with open(os.path.join(args.out, file), 'rb') as f:
            print(file, hashlib.sha256(f.read()).hexdigest(), note)


if __name__ == '__main__':
    main()
