//! COSMO-SkyMed products calibrated as e-GEOS defines it: two synthetic first-generation
//! products (tests/data, written by tests/data/make_csk.py with h5py) read through GDAL's HDF5
//! driver come back as sigma0 = |DN|^2 R_ref^(2 R_exp) sin(alpha_ref) / (F^2 K) at every pixel.

use std::path::PathBuf;
use wakelab_products::{open, ReadOptions};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// The products' attributes: F = 1000, R_ref = 600 km, exponent 1, alpha_ref = 30 degrees,
/// K = 2.5e10, every compensation applied by the processor.
fn factor() -> f64 {
    600_000f64.powi(2) * 30f64.to_radians().sin() / (1000f64.powi(2) * 2.5e10)
}

#[test]
fn detected_and_complex_products_read_as_sigma0() {
    let dgm = open(&data("CSK_synth_DGM_B.h5"), &ReadOptions::default()).unwrap();
    assert_eq!(dgm.image.dim(), (20, 10));
    for ((r, c), &v) in dgm.image.indexed_iter() {
        let dn = ((r * 10 + c) % 500 + 1) as f64;
        let want = dn * dn * factor();
        assert!(
            ((v as f64) - want).abs() <= 1e-6 * want,
            "({r}, {c}): {v} against {want}"
        );
    }
    // DN 1: 7.2e-6, worked out apart by plain arithmetic
    assert!((dgm.image[[0, 0]] as f64 - 7.2e-6).abs() < 1e-6 * 7.2e-6);
    assert_eq!(dgm.meta.polarisation.as_deref(), Some("HH"));
    assert_eq!(dgm.meta.pixel_spacing.map(|s| (s.rows, s.columns)), Some((2.5, 2.5)));
    // its corners placed by GDAL's GCPs: the top-left corner at 45.1 N, 11.9 E
    let corner = dgm.frame.lonlat(&[(0.0, 0.0)]).unwrap()[0];
    assert!(
        (corner.0 - 11.9).abs() < 1e-9 && (corner.1 - 45.1).abs() < 1e-9,
        "{corner:?}"
    );

    // complex: I = index % 5 + 3, Q = 4, |DN|^2 = I^2 + Q^2
    let scs = open(&data("CSK_synth_SCS_B.h5"), &ReadOptions::default()).unwrap();
    for ((r, c), &v) in scs.image.indexed_iter() {
        let i = ((r * 10 + c) % 5 + 3) as f64;
        let want = (i * i + 16.0) * factor();
        assert!(
            ((v as f64) - want).abs() <= 1e-6 * want,
            "({r}, {c}): {v} against {want}"
        );
    }
    // I = 3, Q = 4: 1.8e-4, worked out apart
    assert!((scs.image[[0, 0]] as f64 - 1.8e-4).abs() < 1e-6 * 1.8e-4);

    let err = open(
        &data("CSK_synth_DGM_B.h5"),
        &ReadOptions {
            polarisation: Some("VV".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("holds: HH"), "{err}");
}
