//! Write a Sentinel-1 GRD product in ESA's SAFE layout of any size, its sea a flat -20 dB
//! with 4-look speckle once calibrated and denoised (DN = sqrt(eta + A^2 sigma0)), for
//! benchmarks and trials of `wakelab calibrate` / `wakelab detect` on a whole product.
//!
//! cargo run --release -p wakelab-products --example synthetic_product -- DIR [LINES SAMPLES [dual]]
//! (default 16854 x 25931, an IW GRDH product's size; `dual`: a VH band too, its sea -28 dB,
//! as most IW products are VV + VH)

use wakelab_products::sentinel1::synthetic::{add_polarisation, write_safe, Synthetic};

/// A 4-look gamma variate of mean 1 from (line, pixel): the mean of four exponentials drawn by
/// a hash of the position (splitmix64), so every pixel is reproducible in any order.
fn speckle(l: usize, p: usize) -> f64 {
    let mut x = ((l as u64) << 32) ^ p as u64;
    let mut draw = || {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..4).map(|_| -(1.0 - draw()).ln()).sum::<f64>() / 4.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = std::path::PathBuf::from(args.get(1).expect("usage: synthetic_product DIR [LINES SAMPLES]"));
    let lines = args.get(2).map_or(16854, |v| v.parse().expect("LINES"));
    let samples = args.get(3).map_or(25931, |v| v.parse().expect("SAMPLES"));
    // the LUTs of a product of this size, to compute its digital numbers from
    let luts = Synthetic {
        lines,
        samples,
        since_2_9: true,
        dn: &|_, _| 0,
    };
    let numbers = |l: usize, p: usize, mean: f64| -> u16 {
        if p < 40 || p + 25 >= samples {
            return 0; // the swath's no-data border
        }
        let (lf, pf) = (l as f64, p as f64);
        let eta = luts.noise_range(lf, pf) * luts.noise_azimuth(lf, pf);
        let sigma0 = mean * speckle(l, p);
        (eta + luts.gain(lf, pf).powi(2) * sigma0)
            .sqrt()
            .round()
            .clamp(1.0, 65535.0) as u16
    };
    let (vv, vh) = (|l, p| numbers(l, p, 0.01), |l, p| numbers(l, p, 0.0016));
    std::fs::create_dir_all(&dir).expect("the output directory");
    let safe = write_safe(&dir, &Synthetic { dn: &vv, ..luts });
    if args.get(4).is_some_and(|a| a == "dual") {
        add_polarisation(&safe, &Synthetic { dn: &vh, ..luts }, "VH");
    }
    println!("{}", safe.display());
}
