#!/usr/bin/env python3
"""Regenerate the held-out real SAR ship-wake images: the 20 of bench/held_out_wakes/, with
--second the 16 of bench/held_out_wakes_2/, with --third the 6 of bench/held_out_wakes_3/.

The images are not kept in this repository (third-party content); this script
cuts them, pixel for pixel, out of public GitHub repositories at pinned
commits (four for the first set, three for the second). The hand-drawn wake
lines are the sets' *.geojson.

Usage:
    python3 bench/held_out_wakes.py OUT_DIR [--second | --third | --fourth] [--mirrors DIR] [--compare DIR]

  OUT_DIR     where the 20 PNGs (8-bit greyscale) are written
  --second    the second held-out set instead (bench/held_out_wakes_2/: 16
              images of three other repositories, each named with its commit
              and path in its GeoJSON's "notes" after SOURCE, taken whole)
  --third     the third held-out set (bench/held_out_wakes_3/: 6 images of
              three more repositories, named in the GeoJSONs as for --second)
  --fourth    the fourth (bench/held_out_wakes_4/: SSDD chips of
              Lemon-L7/efficient-pytorch-ship, taken whole as for --second);
              its drawings are written to OUT_DIR too, each with SSDD's own
              ship boxes (VOCdevkit/VOC2007/Annotations/ID.xml at the same
              commit) added as Polygons of "kind": "ship" and "ships_drawn":
              true, so that score_real_wakes.py scores the ship search
  --mirrors   folder holding the four repositories (default /work/.mirror);
              each is looked up as DIR/OWNER+NAME/repo, DIR/OWNER+NAME or
              DIR/NAME (bare repository or a clone with a work tree)
  --compare   folder with earlier outputs: report per image whether the
              pixels are equal, else how many differ
It prints each output's name and sha256 at the end.

Needs: python3 with numpy, Pillow and scipy (scipy.io.loadmat reads the
TerraSAR-X .mat file); git on PATH. Tested with numpy 2.4, Pillow 13.0,
scipy 1.17. Fetching the sources is the user's job, e.g. into DIR:
    git clone https://github.com/libzzluo/OpenSARWake DIR/OpenSARWake
    git -C DIR/OpenSARWake checkout cc86027e4005d84daaa6b4314d2799ef1583b4f5
    git clone https://github.com/oktaykarakus/AssenSAR-Wake-Detector DIR/AssenSAR-Wake-Detector
    git -C DIR/AssenSAR-Wake-Detector checkout d7f7fc2ccb642df185a5327336db06104be72990
    git clone https://github.com/jascubero/Automated-ship-detection DIR/Automated-ship-detection
    git -C DIR/Automated-ship-detection checkout 59ea6f7455ed2815a663f6c7cba5321742f03923
    git clone https://github.com/kunal15145/Ship_Wake_Detection DIR/Ship_Wake_Detection
    git -C DIR/Ship_Wake_Detection checkout 9480d4852e8f5f76088760375c3a1aa1e722d8f8
(files are read with `git show COMMIT:PATH`, so the checkout is optional).

Preparation (crops only, no resampling):
  osw_01..12  OpenSARWake README figure samples.jpg, a 4x3 grid of chips: cut
              at the white gutters (columns/rows >95 % white), 2 px inset,
              grey = (R+B)//2; the burned-in green boxes (G-max(R,B) > 25 on
              the whole figure, dilated 3 times with the 4-neighbourhood) are
              filled with unmasked grey pixels of the same panel drawn at
              random offsets in [-19,19]^2 with Chebyshev distance >= 4
              (numpy default_rng(panel number), so the fill is reproducible).
  tsx_01      AssenSAR testImage.mat 'Image' (TerraSAR-X), round(255*Image).
  s1jas_01    jascubero Fig/sar_image.png, white margin + frame cut (6 px).
  kun_01..06  kunal15145 'Live SAR images' as greyscale (PIL convert('L'));
              live10 loses its 4-px black left border.
Second set: every file is grey stored as RGB (R == G == B, checked); its R
channel is kept whole, no crop or resampling (the HRSID JPEGs as Pillow's
libjpeg decodes them). Its repositories:
    https://github.com/atlan-antillia/TensorFlow-FlexUNet-Image-Segmentation-HRSID-Satellite-Imagery-Ship (15d0d587)
    https://github.com/chaozhong2010/HRSID (2d682fe0)
    https://github.com/lewisFarley403/Dark-ship-detection (b68744df)
Third set: as the second, R channel kept, with two exceptions. eob_01 (an EO
Browser screenshot) is cropped to rows 34..757, dropping the header, scale bar
and credit burned in above and below the sea. The hrs_* chips (HRSID test
chips as TerrencePai's keypoint figures saved them, lossless PNG) carry
magenta ship boxes and keypoint dots around their ships: those pixels (where
R, G and B differ; under 1 % of a chip), dilated once with the
4-neighbourhood, are filled as the OpenSARWake boxes are (numpy
default_rng(chip number)). Its repositories:
    https://github.com/alexmak001/SAR-satelite-image-ship-detection (6ca3ee58)
    https://github.com/ioEclipse/SAR-SHIP-DETECTION (1a6df292)
    https://github.com/TerrencePai/SAR_Ship_keypoint_detection (0b1fe257)
"""
import argparse, hashlib, io, json, os, re, subprocess, sys
try:
    import numpy as np
    from PIL import Image
    from scipy.io import loadmat
except ImportError as missing:
    sys.exit(f"held_out_wakes.py needs numpy, Pillow and scipy ({missing}): pip install numpy pillow scipy")

OSW = ('libzzluo/OpenSARWake', 'cc86027e4005d84daaa6b4314d2799ef1583b4f5')
TSX = ('oktaykarakus/AssenSAR-Wake-Detector', 'd7f7fc2ccb642df185a5327336db06104be72990')
JAS = ('jascubero/Automated-ship-detection', '59ea6f7455ed2815a663f6c7cba5321742f03923')
KUN = ('kunal15145/Ship_Wake_Detection', '9480d4852e8f5f76088760375c3a1aa1e722d8f8')
SSDD = ('Lemon-L7/efficient-pytorch-ship', '05b50517ad00c01ab513e53832e9dd25edace7a0')
LIVE = 'Dataset/Live SAR images Dataset/'
# kun_NN: (file, crop as (y0, y1, x0, x1) or None)
KUN_FILES = [('Live3.png', None), ('live1.png', None), ('live5.png', None),
             ('live6.png', None), ('live7.png', None), ('live10.png', (0, None, 4, None))]


def git_dir(mirrors, repo):
    owner, name = repo.split('/')
    for d in (f'{owner}+{name}/repo', f'{owner}+{name}', name):
        p = os.path.join(mirrors, d)
        for g in (os.path.join(p, '.git'), p):
            if os.path.isfile(os.path.join(g, 'HEAD')) and os.path.isdir(os.path.join(g, 'objects')):
                return g
    sys.exit(f'{repo} not found under {mirrors} (see the docstring for git clone commands)')


def blob(mirrors, src, path):
    repo, commit = src
    return subprocess.run(['git', '--git-dir', git_dir(mirrors, repo), 'show', f'{commit}:{path}'],
                          check=True, capture_output=True).stdout


def runs(flags):
    """(start, end_exclusive) of each run of True."""
    f = np.concatenate([[False], flags, [False]]).astype(np.int8)
    d = np.diff(f)
    return list(zip(np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]))


def dilate4(m, times):
    for _ in range(times):
        o = m.copy()
        o[1:] |= m[:-1]; o[:-1] |= m[1:]; o[:, 1:] |= m[:, :-1]; o[:, :-1] |= m[:, 1:]
        m = o
    return m


def fill(grey, mask, rng, rmin=4, rmax=19):
    """Replace masked pixels by unmasked ones at random offsets rmin..rmax (Chebyshev)."""
    out = grey.copy()
    h, w = grey.shape
    ys, xs = np.nonzero(mask)
    todo = np.arange(ys.size)
    for _ in range(10000):
        if todo.size == 0:
            return out
        dy = rng.integers(-rmax, rmax + 1, todo.size)
        dx = rng.integers(-rmax, rmax + 1, todo.size)
        sy, sx = ys[todo] + dy, xs[todo] + dx
        ok = (np.maximum(abs(dy), abs(dx)) >= rmin) & (sy >= 0) & (sy < h) & (sx >= 0) & (sx < w)
        ok[ok] = ~mask[sy[ok], sx[ok]]
        out[ys[todo[ok]], xs[todo[ok]]] = grey[sy[ok], sx[ok]]
        todo = todo[~ok]
    raise RuntimeError('fill: some masked pixels have no unmasked source in reach')


def opensarwake(mirrors):
    rgb = np.asarray(Image.open(io.BytesIO(blob(mirrors, OSW, 'samples.jpg'))).convert('RGB')).astype(np.int16)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    white = rgb.min(axis=2) >= 245
    # panels lie between the white gutters
    cols = [(a + 2, e - 2) for a, e in runs(white.mean(axis=0) <= 0.95)]
    rows = [(a + 2, e - 2) for a, e in runs(white.mean(axis=1) <= 0.95)]
    assert len(cols) == 4 and len(rows) == 3, (cols, rows)
    mask = dilate4(g - np.maximum(r, b) > 25, 3)
    grey = ((r + b) // 2).astype(np.uint8)
    out = {}
    for i, (y0, y1) in enumerate(rows):
        for j, (x0, x1) in enumerate(cols):
            n = 4 * i + j + 1
            out[f'osw_{n:02d}'] = fill(grey[y0:y1, x0:x1], mask[y0:y1, x0:x1], np.random.default_rng(n))
    return out


def terrasar(mirrors):
    img = loadmat(io.BytesIO(blob(mirrors, TSX, 'images/testImage.mat')))['Image']
    return {'tsx_01': np.clip(np.round(img * 255), 0, 255).astype(np.uint8)}


def jascubero(mirrors):
    im = Image.open(io.BytesIO(blob(mirrors, JAS, 'Conference Paper/Fig/sar_image.png'))).convert('L')
    a = np.asarray(im)
    return {'s1jas_01': a[6:a.shape[0] - 6, 6:a.shape[1] - 6]}


def kunal(mirrors):
    out = {}
    for k, (f, crop) in enumerate(KUN_FILES, 1):
        a = np.asarray(Image.open(io.BytesIO(blob(mirrors, KUN, LIVE + f))).convert('L'))
        if crop:
            a = a[crop[0]:crop[1], crop[2]:crop[3]]
        out[f'kun_{k:02d}'] = a
    return out


def second_set(mirrors, folder='held_out_wakes_2'):
    """The second set (and the fourth, `folder`): each GeoJSON's notes begin
    `SOURCE owner/name@commit:path (licence)`."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), folder)
    images = {}
    for f in sorted(os.listdir(here)):
        if not f.endswith('.geojson'):
            continue
        with open(os.path.join(here, f)) as g:
            source = json.load(g)['notes'].split()[1]
        repo, rest = source.split('@', 1)
        commit, path = rest.split(':', 1)
        rgb = np.asarray(Image.open(io.BytesIO(blob(mirrors, (repo, commit), path))).convert('RGB'))
        if not ((rgb[..., 0] == rgb[..., 1]).all() and (rgb[..., 0] == rgb[..., 2]).all()):
            sys.exit(f'{source}: not a grey image (R, G and B differ)')
        images[f[:-len('.geojson')]] = rgb[..., 0].copy()
    return images


# the third set's crops, (y0, y1, x0, x1)
THIRD_CROPS = {'eob_01': (34, 758, 0, 1086)}


def ssdd_ship_boxes(mirrors, chip):
    """SSDD's boxes of the chip `chip` (its 6-digit ID) as (xmin, ymin, xmax, ymax) pixels (bench/ssdd_ships.py
    reads them too)."""
    xml = blob(mirrors, SSDD, f'VOCdevkit/VOC2007/Annotations/{chip}.xml').decode()
    boxes = re.findall(r'<xmin>([\d.]+)</xmin>\s*<ymin>([\d.]+)</ymin>\s*'
                       r'<xmax>([\d.]+)</xmax>\s*<ymax>([\d.]+)</ymax>', xml)
    return [tuple(float(v) for v in b) for b in boxes]


def fourth_drawings(mirrors, out_dir):
    """The fourth set's drawings in `out_dir`, each with SSDD's ship boxes added."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'held_out_wakes_4')
    for f in sorted(os.listdir(here)):
        if not f.endswith('.geojson'):
            continue
        with open(os.path.join(here, f)) as g:
            drawing = json.load(g)
        boxes = ssdd_ship_boxes(mirrors, f[len('ssdd_'):-len('.geojson')])
        if not boxes:
            sys.exit(f'{f}: no ship box in its SSDD annotation')
        for x0, y0, x1, y1 in boxes:
            drawing['features'].append({
                'type': 'Feature',
                'properties': {'kind': 'ship', 'source': 'SSDD annotation'},
                'geometry': {'type': 'Polygon',
                             'coordinates': [[[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]]}})
        drawing['wakelab']['ships_drawn'] = True
        path = os.path.join(out_dir, f)
        with open(path + '.tmp', 'w') as g:
            json.dump(drawing, g, indent=1)
        os.replace(path + '.tmp', path)


def third_set(mirrors):
    """The third set: sources as the second's (a path may hold spaces), crops and overlays as the
    docstring says."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'held_out_wakes_3')
    images = {}
    for f in sorted(os.listdir(here)):
        if not f.endswith('.geojson'):
            continue
        name = f[:-len('.geojson')]
        with open(os.path.join(here, f)) as g:
            notes = json.load(g)['notes']
        m = re.match(r'SOURCE (\S+)@([0-9a-f]{40}):(.+?\.(?:png|jpg)) \(', notes)
        if not m:
            sys.exit(f'{f}: notes do not start with SOURCE owner/name@commit:path (licence)')
        repo, commit, path = m.groups()
        rgb = np.asarray(Image.open(io.BytesIO(blob(mirrors, (repo, commit), path))).convert('RGB'))
        if name in THIRD_CROPS:
            y0, y1, x0, x1 = THIRD_CROPS[name]
            rgb = rgb[y0:y1, x0:x1]
        r = rgb[..., 0].copy()
        colour = (rgb[..., 0] != rgb[..., 1]) | (rgb[..., 0] != rgb[..., 2])
        if name.startswith('hrs_'):
            if colour.mean() >= 0.01:
                sys.exit(f'{name}: {colour.mean():.1%} of the pixels are coloured, more than the ship boxes')
            r = fill(r, dilate4(colour, 1), np.random.default_rng(int(name[4:])))
        elif colour.any():
            sys.exit(f'{name}: not a grey image (R, G and B differ)')
        images[name] = r
    return images


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('out_dir')
    ap.add_argument('--mirrors', default='/work/.mirror')
    ap.add_argument('--compare', default=None)
    which = ap.add_mutually_exclusive_group()
    which.add_argument('--second', action='store_true')
    which.add_argument('--third', action='store_true')
    which.add_argument('--fourth', action='store_true')
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    images = {}
    fourth = lambda mirrors: second_set(mirrors, 'held_out_wakes_4')
    parts = ((second_set,) if a.second else (third_set,) if a.third else (fourth,) if a.fourth
             else (kunal, opensarwake, jascubero, terrasar))
    for part in parts:
        images.update(part(a.mirrors))
    for name in sorted(images):
        # a temporary name, then the real one: bench/real_wakes.sh takes the last image's presence
        # for a finished set
        path = os.path.join(a.out_dir, name + '.png')
        Image.fromarray(np.ascontiguousarray(images[name], dtype=np.uint8), 'L').save(path + '.tmp', format='PNG')
        os.replace(path + '.tmp', path)
    if a.fourth:
        fourth_drawings(a.mirrors, a.out_dir)
    if a.compare:
        for name in sorted(images):
            old = np.asarray(Image.open(os.path.join(a.compare, name + '.png')))
            new = images[name]
            same = old.shape == new.shape and (old == new).all()
            diff = 'shape differs' if old.shape != new.shape else f'{int((old != new).sum())} px differ'
            print(f'compare {name}: {"equal" if same else diff}')
    for name in sorted(images):
        with open(os.path.join(a.out_dir, name + '.png'), 'rb') as f:
            print(f'{name}.png {hashlib.sha256(f.read()).hexdigest()}')


if __name__ == '__main__':
    main()
