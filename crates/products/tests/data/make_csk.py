#!/usr/bin/python3
"""Writes the two synthetic COSMO-SkyMed (first generation) HDF5 products of tests/cosmo.rs:
DGM_B (uint16 DN = index % 500 + 1) and SCS_B (I = index % 5 + 3, Q = 4), 20 x 10 pixels, with the
calibration attributes of the e-GEOS note. Needs h5py (apt-get install python3-h5py).
Run: python3 make_csk.py crates/products/tests/data"""
import sys, numpy as np, h5py

def s(x): return np.bytes_(x)  # CSK stores fixed-length byte strings

def make(fn, product_type="DGM_B", complex_=False):
    ny, nx = 20, 10
    with h5py.File(fn, "w") as f:
        a = f.attrs
        a["Mission ID"] = s("CSK")
        a["Product Type"] = s(product_type)
        a["Acquisition Mode"] = s("HIMAGE")
        a["Rescaling Factor"] = 1000.0
        a["Reference Slant Range"] = 600000.0
        a["Reference Slant Range Exponent"] = 1.0
        a["Reference Incidence Angle"] = 30.0
        a["Calibration Constant Compensation Flag"] = np.uint8(0)
        a["Range Spreading Loss Compensation Geometry"] = s("GEOMETRIC")
        a["Incidence Angle Compensation Geometry"] = s("ELLIPSOID")
        a["Scene Centre Geodetic Coordinates"] = np.array([45.0, 12.0, 0.0])
        a["Ellipsoid Designator"] = s("WGS84")
        g = f.create_group("S01")
        g.attrs["Polarisation"] = s("HH")
        g.attrs["Calibration Constant"] = 2.5e10
        if complex_:
            i = (np.arange(ny * nx).reshape(ny, nx) % 5 + 3).astype(np.int16)
            d = g.create_dataset("SBI", data=np.stack([i, np.full((ny, nx), 4, np.int16)], axis=-1))
        else:
            d = g.create_dataset("SBI", data=(np.arange(ny*nx).reshape(ny, nx) % 500 + 1).astype(np.uint16))
        d.attrs["Top Left Geodetic Coordinates"] = np.array([45.1, 11.9, 0.0])
        d.attrs["Top Right Geodetic Coordinates"] = np.array([45.1, 12.1, 0.0])
        d.attrs["Bottom Left Geodetic Coordinates"] = np.array([44.9, 11.9, 0.0])
        d.attrs["Bottom Right Geodetic Coordinates"] = np.array([44.9, 12.1, 0.0])
        d.attrs["Line Spacing"] = 2.5
        d.attrs["Column Spacing"] = 2.5

if __name__ == "__main__":
    base = sys.argv[1] if len(sys.argv) > 1 else "."
    make(f"{base}/CSK_synth_DGM_B.h5")
    make(f"{base}/CSK_synth_SCS_B.h5", "SCS_B", complex_=True)
