//! The commands that print reports: `idp`, `spectrum`, `sar sigma0`, `optics`.

use crate::cli::ConfigArgs;
use crate::Result;
use std::path::Path;
use wakelab_core::config::{Polarisation, WakelabConfig};
use wakelab_core::units::RadarBand;

/// `wakelab idp`.
pub fn idp(config: &ConfigArgs, json: bool, write: Option<&Path>) -> Result<()> {
    let cfg = config.load()?;
    let idp = wakelab_hydro::initial_data_plane(&cfg);
    if json {
        println!("{}", serde_json::to_string_pretty(&idp.scalars)?);
    } else {
        print_idp(&idp.scalars);
    }
    if let Some(dir) = write {
        for f in wakelab_hydro::output::write_idp_fields(dir, &cfg)? {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(())
}

/// `wakelab spectrum`.
pub fn spectrum(config: &ConfigArgs, wind: Option<f64>, incidence: Option<f64>, json: bool) -> Result<()> {
    let cfg = config.load_with(wind, incidence)?;
    let report = spectrum_report(&cfg);
    emit(&report, json)
}

/// `wakelab optics`.
pub fn optics(
    config: &ConfigArgs,
    wavelength: f64,
    salinity: Option<f64>,
    temperature: Option<f64>,
    incidence: Option<f64>,
    json: bool,
) -> Result<()> {
    let mut cfg = config.load()?;
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
    let index = wakelab_sensors::optics::seawater_index(wavelength, s, t);
    let theta = cfg.platform.incidence.to_radians();
    let (rho_s, rho_p) = wakelab_sensors::optics::fresnel_reflectance(wakelab_sensors::optics::N_AIR, index, theta);
    let flat: Vec<serde_json::Value> = wakelab_sensors::IrBand::ALL
        .iter()
        .map(|&band| {
            let view = wakelab_sensors::ir::IrView::new(&cfg, band);
            let terms = view.facet(0.0, 0.0, env.temperature.at_depth(0.0) + 273.15);
            let (lo, hi) = band.range();
            serde_json::json!({
                "band": band.name(),
                "wavelength_range_um": [lo, hi],
                "radiance": terms.total(),
                "brightness_temperature_k": wakelab_sensors::planck::brightness_temperature(lo, hi, terms.total()),
                "terms": terms,
            })
        })
        .collect();
    let report = serde_json::json!({
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
    });
    emit(&report, json)
}

/// `wakelab sar sigma0`.
#[allow(clippy::too_many_arguments)]
pub fn sar_sigma0(
    config: &ConfigArgs,
    wind: Option<f64>,
    band: &str,
    polarisation: Option<&str>,
    incidence: Option<f64>,
    look: f64,
    json: bool,
) -> Result<()> {
    let mut cfg = config.load_with(wind, incidence)?;
    if let Some(p) = polarisation {
        cfg.sar.polarisation = match p.to_lowercase().as_str() {
            "vv" => Polarisation::Vv,
            "hh" => Polarisation::Hh,
            other => anyhow::bail!("--polarisation {other}: must be vv or hh"),
        };
    }
    cfg.validate()?;
    let band = match band.to_uppercase().as_str() {
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

fn print_idp(s: &wakelab_hydro::IdpScalars) {
    print_json_table(&serde_json::to_value(s).expect("serialisable"));
}

/// Print a report as JSON or as a table.
fn emit(report: &impl serde::Serialize, json: bool) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(report)?);
    } else {
        print_json_table(&serde_json::to_value(report)?);
    }
    Ok(())
}

/// Print a JSON object as aligned `key = value` lines.
fn print_json_table(value: &serde_json::Value) {
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            match v {
                serde_json::Value::Array(items) => {
                    for item in items {
                        println!("{k}:");
                        print_json_table(item);
                    }
                }
                _ => println!("{k:>26} = {}", v.as_f64().map_or(v.to_string(), |x| format!("{x:.6e}"))),
            }
        }
    }
}

/// What `wakelab spectrum` reports.
#[derive(serde::Serialize)]
struct SpectrumReport {
    model: wakelab_core::config::SpectrumModel,
    wind_speed: f64,
    wind_direction_deg: f64,
    swell_amplitude: f64,
    swell_wavelength: f64,
    #[serde(flatten)]
    summary: wakelab_surface::spectrum::SpectrumSummary,
    incidence_deg: f64,
    look_direction_deg: f64,
    bragg: Vec<BraggReport>,
}

#[derive(serde::Serialize)]
struct BraggReport {
    band: &'static str,
    frequency_hz: f64,
    bragg_wavenumber: f64,
    bragg_wavelength_m: f64,
    /// F(k_B) towards the sensor (m^4).
    density_towards: f64,
    /// F(-k_B) away from the sensor (m^4).
    density_away: f64,
    /// Omnidirectional Psi(k_B) (m^3).
    omnidirectional: f64,
}

fn spectrum_report(cfg: &WakelabConfig) -> SpectrumReport {
    let sea = wakelab_surface::background_spectrum(cfg);
    let bragg = wakelab_core::units::RadarBand::ALL
        .iter()
        .map(|&band| {
            let (t, a) = wakelab_surface::bragg_vectors(cfg, band);
            let k = t.magnitude();
            BraggReport {
                band: band.name(),
                frequency_hz: band.frequency(),
                bragg_wavenumber: k,
                bragg_wavelength_m: 2.0 * std::f64::consts::PI / k,
                density_towards: sea.directional(t.kx, t.ky),
                density_away: sea.directional(a.kx, a.ky),
                omnidirectional: sea.wind_omni(k),
            }
        })
        .collect();
    let env = &cfg.environment;
    SpectrumReport {
        model: cfg.sea.spectrum,
        wind_speed: env.wind.speed,
        wind_direction_deg: env.wind.direction,
        swell_amplitude: if env.swell.angle().is_some() {
            env.swell.amplitude
        } else {
            0.0
        },
        swell_wavelength: env.swell.wavelength,
        // slopes of all waves longer than 6 mm (k < 1000 rad/m, the gravity-capillary range)
        summary: sea.summary(1000.0),
        incidence_deg: cfg.platform.incidence,
        look_direction_deg: cfg.platform.look_direction,
        bragg,
    }
}
