//! What `wakelab optics` prints: the sea water's refractive index at one wavelength (Eq. (3.8)),
//! its Fresnel reflectance (Eqs. (3.9)-(3.13)) and Kirchhoff emissivity (1 - rho) at the configured
//! incidence, and the radiance of a flat sea in each infrared band (Eq. (3.5) of a level facet).

use wakelab_core::config::WakelabConfig;

/// What `wakelab optics` prints for `wavelength` (micrometres), with the configuration's surface
/// salinity, temperature and incidence unless given; an error names the flag out of range.
pub fn optics_of_config(
    cfg: &WakelabConfig,
    wavelength: f64,
    salinity: Option<f64>,
    temperature: Option<f64>,
    incidence: Option<f64>,
) -> Result<serde_json::Value, String> {
    let mut cfg = cfg.clone();
    if let Some(i) = incidence {
        if !(0.0..90.0).contains(&i) {
            return Err(format!("--incidence {i}: must be in [0, 90) degrees"));
        }
        // the optics hold at any angle; the flat-sea radiance uses it as the view angle
        cfg.platform.incidence = i;
    }
    if !(0.2..=200.0).contains(&wavelength) {
        return Err(format!("--wavelength {wavelength}: must be in [0.2, 200] micrometres"));
    }
    let env = &cfg.environment;
    let s = salinity.unwrap_or(env.salinity.at_depth(0.0));
    let t = temperature.unwrap_or(env.temperature.at_depth(0.0));
    if !(0.0..=42.0).contains(&s) || !(-2.0..=40.0).contains(&t) {
        return Err("--salinity must be in [0, 42] PSU and --temperature in [-2, 40] deg C".into());
    }
    Ok(optics_report(&cfg, wavelength, s, t))
}

/// The optics of sea water of salinity `s` (PSU) and temperature `t` (deg C) at `wavelength`
/// (micrometres), seen at the configuration's incidence, as JSON.
pub fn optics_report(cfg: &WakelabConfig, wavelength: f64, s: f64, t: f64) -> serde_json::Value {
    let env = &cfg.environment;
    let index = crate::optics::seawater_index(wavelength, s, t);
    let theta = cfg.platform.incidence.to_radians();
    let (rho_s, rho_p) = crate::optics::fresnel_reflectance(crate::optics::N_AIR, index, theta);
    let flat: Vec<serde_json::Value> = crate::IrBand::ALL
        .iter()
        .map(|&band| {
            let view = crate::ir::IrView::new(cfg, band);
            let terms = view.facet(0.0, 0.0, env.temperature.at_depth(0.0) + 273.15);
            let (lo, hi) = band.range();
            serde_json::json!({
                "band": band.name(),
                "wavelength_range_um": [lo, hi],
                "radiance": terms.total(),
                "brightness_temperature_k": crate::planck::brightness_temperature(lo, hi, terms.total()),
                "terms": terms,
            })
        })
        .collect();
    serde_json::json!({
        "wavelength_um": wavelength,
        "salinity": s,
        "temperature_c": t,
        "incidence_deg": cfg.platform.incidence,
        "n": index.re,
        "kappa": -index.im,
        "rho_s": rho_s,
        "rho_p": rho_p,
        "rho": 0.5 * (rho_s + rho_p),
        "emissivity": 1.0 - 0.5 * (rho_s + rho_p),
        "flat_sea_radiance": flat,
    })
}
