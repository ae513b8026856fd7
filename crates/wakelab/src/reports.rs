//! The commands that print reports: `idp`, `spectrum`, `sar sigma0`, `optics`.

use crate::cli::{ConfigArgs, IdpArgs, OpticsArgs, Sigma0Args, SpectrumArgs};
use crate::Result;

/// `wakelab idp`.
pub fn idp(args: &IdpArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let idp = wakelab_hydro::initial_data_plane(&cfg);
    emit(&idp.scalars, args.json)?;
    if let Some(dir) = args.write.as_deref() {
        for f in wakelab_hydro::output::write_idp_fields(dir, &cfg)? {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(())
}

/// `wakelab spectrum`.
pub fn spectrum(args: &SpectrumArgs) -> Result<()> {
    let report = wakelab_surface::spectrum_report::spectrum_report(&args.config.load_with(args.wind, args.incidence)?);
    emit(&report, args.json)
}

/// `wakelab optics`.
pub fn optics(args: &OpticsArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let (w, s, t, i) = (args.wavelength, args.salinity, args.temperature, args.incidence);
    let report = wakelab_sensors::optics_report::optics_of_config(&cfg, w, s, t, i).map_err(anyhow::Error::msg)?;
    emit(&report, args.json)
}

/// `wakelab sar sigma0`.
pub fn sar_sigma0(args: &Sigma0Args) -> Result<()> {
    let mut cfg = args.config.load_with(args.wind, args.incidence)?;
    cfg.sar.polarisation = args.polarisation.unwrap_or(cfg.sar.polarisation);
    let report = wakelab_sensors::sigma0_report::sigma0_of_config(&cfg, args.band, args.look, args.cell)?;
    emit(&report, args.json)
}

/// `wakelab config show`: the effective configuration as TOML.
pub fn config_show(config: &ConfigArgs) -> Result<()> {
    print!("{}", config.load()?.to_toml_string());
    Ok(())
}

/// Print a report as JSON or as aligned lines.
fn emit(report: &impl serde::Serialize, json: bool) -> Result<()> {
    print!("{}", wakelab_core::io::text::report_text(report, json)?);
    Ok(())
}
