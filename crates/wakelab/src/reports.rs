//! The commands that print reports: `idp`, `spectrum`, `sar sigma0`, `optics`.

use crate::cli::{IdpArgs, OpticsArgs, Sigma0Args, SpectrumArgs};
use crate::Result;
use wakelab_core::config::Polarisation;
use wakelab_core::units::RadarBand;

/// `wakelab idp`.
pub fn idp(args: &IdpArgs) -> Result<()> {
    let (json, write) = (args.json, args.write.as_deref());
    let cfg = args.config.load()?;
    let idp = wakelab_hydro::initial_data_plane(&cfg);
    emit(&idp.scalars, json)?;
    if let Some(dir) = write {
        for f in wakelab_hydro::output::write_idp_fields(dir, &cfg)? {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(())
}

/// `wakelab spectrum`.
pub fn spectrum(args: &SpectrumArgs) -> Result<()> {
    let cfg = args.config.load_with(args.wind, args.incidence)?;
    let report = wakelab_surface::spectrum_report::spectrum_report(&cfg);
    emit(&report, args.json)
}

/// `wakelab optics`.
pub fn optics(args: &OpticsArgs) -> Result<()> {
    let OpticsArgs {
        wavelength,
        salinity,
        temperature,
        incidence,
        json,
        ..
    } = *args;
    let mut cfg = args.config.load()?;
    if let Some(i) = incidence {
        if !(0.0..90.0).contains(&i) {
            anyhow::bail!("--incidence {i}: must be in [0, 90) degrees");
        }
        // the optics hold at any angle; the flat-sea radiance uses it as the view angle
        cfg.platform.incidence = i;
    }
    if !(0.2..=200.0).contains(&wavelength) {
        anyhow::bail!("--wavelength {wavelength}: must be in [0.2, 200] micrometres");
    }
    let env = &cfg.environment;
    let s = salinity.unwrap_or(env.salinity.at_depth(0.0));
    let t = temperature.unwrap_or(env.temperature.at_depth(0.0));
    if !(0.0..=42.0).contains(&s) || !(-2.0..=40.0).contains(&t) {
        anyhow::bail!("--salinity must be in [0, 42] PSU and --temperature in [-2, 40] deg C");
    }
    let report = wakelab_sensors::optics_report::optics_report(&cfg, wavelength, s, t);
    emit(&report, json)
}

/// `wakelab sar sigma0`.
pub fn sar_sigma0(args: &Sigma0Args) -> Result<()> {
    let (look, json) = (args.look, args.json);
    let mut cfg = args.config.load_with(args.wind, args.incidence)?;
    if let Some(p) = &args.polarisation {
        cfg.sar.polarisation = match p.to_lowercase().as_str() {
            "vv" => Polarisation::Vv,
            "hh" => Polarisation::Hh,
            other => anyhow::bail!("--polarisation {other}: must be vv or hh"),
        };
    }
    cfg.validate()?;
    let band = match args.band.to_uppercase().as_str() {
        "S" => RadarBand::S,
        "C" => RadarBand::C,
        "X" => RadarBand::X,
        other => anyhow::bail!("--band {other}: must be S, C or X"),
    };
    let sea = wakelab_surface::background_spectrum(&cfg);
    let env = &cfg.environment;
    let eps = wakelab_sensors::sar_image::surface_permittivity(&cfg, band);
    let report = wakelab_sensors::sar::sigma0_of_sea(
        &sea,
        band,
        eps,
        cfg.sar.polarisation,
        (env.wind.direction - look).to_radians(),
        cfg.platform.incidence,
        cfg.scene.pixel_spacing,
    );
    emit(&report, json)
}

/// Print a report as JSON or as aligned lines.
fn emit(report: &impl serde::Serialize, json: bool) -> Result<()> {
    print!("{}", wakelab_core::io::text::report_text(report, json)?);
    Ok(())
}
