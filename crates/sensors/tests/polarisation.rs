//! The open sea's polarisation ratio against the published C-band models.

use std::f64::consts::PI;
use wakelab_core::config::Polarisation;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_sensors::gmf::CELL_SIZE;
use wakelab_sensors::permittivity::seawater_permittivity;
use wakelab_sensors::sigma0_report::sigma0_of_sea;
use wakelab_surface::spectrum::SeaSpectrum;

/// The empirical polarisation ratio PR = sigma_VV / sigma_HH = ((1 + 2 tan^2) / (1 + a tan^2))^2
/// in dB: a = 0.6 (Thompson, Elfouhaily & Chapron 1998, IGARSS) and a = 1 (Vachon & Dobson
/// 2000, Can. J. Remote Sens. 26, for RADARSAT), the two forms C-band wind retrievals use.
fn published_ratio_db(incidence_deg: f64, a: f64) -> f64 {
    let t2 = incidence_deg.to_radians().tan().powi(2);
    20.0 * ((1.0 + 2.0 * t2) / (1.0 + a * t2)).log10()
}

/// The polarisation ratio that Mouche et al. (2005, IEEE Trans. Geosci. Remote Sens. 43,
/// 753-769) fitted to ENVISAT ASAR against ECMWF winds, PR = A exp(B theta) + C (theta in
/// degrees), looking up-wind and cross-wind, in dB.
fn asar_ratio_db(incidence_deg: f64, cross_wind: bool) -> f64 {
    let (a, b, c) = if cross_wind {
        (0.00782194, 0.121405, 0.992839)
    } else {
        (0.00650704, 0.128983, 0.992839)
    };
    10.0 * (a * (b * incidence_deg).exp() + c).log10()
}

/// wakelab's VV/HH ratio of the open sea (Bragg, specular and breakers together) rises with
/// incidence, lies within 1.2 dB of the band between those two forms and within 2.1 dB of
/// ASAR's at 20-45 degrees, 5-15 m/s, up- and cross-wind. Measured: at most 0.7 dB below the
/// band (20 degrees, where the polarisation-blind specular and breaking terms weigh most) and
/// 1.1 dB above it; against ASAR within 0.8 dB at 20-25 degrees and at 15 m/s, but up to 2.0 dB
/// high at 40-45 degrees and 5 m/s, where wakelab's sea is nearly pure Bragg (too little
/// polarisation-blind scattering from breakers at low wind).
#[test]
fn the_polarisation_ratio_lies_between_the_published_forms() {
    let c = WakelabConfig::default();
    let eps = seawater_permittivity(RadarBand::C.frequency(), 15.0, 35.0);
    let (mut below, mut above, mut off_asar) = (0.0f64, 0.0f64, 0.0f64);
    for wind in [5.0, 10.0, 15.0] {
        let spectrum = SeaSpectrum::wind_sea(&c.sea, wind, 0.0, 9.81);
        for look in [PI, PI / 2.0] {
            let mut last = f64::NEG_INFINITY;
            for inc in [20.0, 25.0, 30.0, 35.0, 40.0, 45.0] {
                let db =
                    |p: Polarisation| sigma0_of_sea(&spectrum, RadarBand::C, eps, p, look, inc, CELL_SIZE).sigma0_db;
                let ratio = db(Polarisation::Vv) - db(Polarisation::Hh);
                let (lo, hi) = (published_ratio_db(inc, 1.0), published_ratio_db(inc, 0.6));
                below = below.max(lo - ratio);
                above = above.max(ratio - hi);
                assert!(
                    ratio > lo - 1.2 && ratio < hi + 1.2,
                    "{wind} m/s {inc} deg: PR {ratio:.2} dB, published {lo:.2}-{hi:.2}"
                );
                let asar = asar_ratio_db(inc, look == PI / 2.0);
                assert!(
                    (ratio - asar).abs() < 2.1,
                    "{wind} m/s {inc} deg: PR {ratio:.2} dB, ASAR {asar:.2}"
                );
                off_asar = off_asar.max((ratio - asar).abs());
                assert!(ratio > last, "{wind} m/s {inc} deg: PR {ratio:.2} not above {last:.2}");
                last = ratio;
            }
        }
    }
    eprintln!("PR against the published band: at most {below:.2} dB below, {above:.2} dB above; against ASAR's: within {off_asar:.2} dB");
}
