//! hydro -> surface -> sensors: one C-band sigma0 image of the default scene, as a PNG.
//!
//! `cargo run --release --example sigma0_image [OUT.png]` (under a minute on 2 cores).

use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "sigma0_c.png".into());
    // the embedded default: the DDG 5415 at 10 m/s on the `quick` grid, 6 m/s wind
    let config = WakelabConfig::default();
    // stage 1 (spec 2.1): the wake's currents, turbulence and films at the surface, x = U t
    let wake = wakelab_hydro::simulate_surface_map(&config)?;
    // stage 2 (spec 2.2-2.3): surfactants, the wake-modulated spectrum, a random sea surface
    let sea = wakelab_surface::simulate_surface(&config, Some(&wake));
    // stage 3 (spec chapter 3): the SAR image in C band
    let image = wakelab_sensors::render_sar(&config, &sea, RadarBand::C);
    let (rows, cols) = image.sigma0.dim();
    let db: Vec<f32> = image
        .sigma0
        .iter()
        .map(|s| (10.0 * s.max(1e-6).log10()) as f32)
        .collect();
    let mean = db.iter().sum::<f32>() / db.len() as f32;
    println!("C-band VV sigma0: {rows} x {cols} px, mean {mean:.1} dB");
    wakelab_core::io::geotiff::write_quicklook(
        out.as_ref(),
        &db,
        rows,
        cols,
        (mean - 8.0).into(),
        (mean + 8.0).into(),
    )?;
    println!("wrote {out} (black {:.0} dB, white {:.0} dB)", mean - 8.0, mean + 8.0);
    Ok(())
}
