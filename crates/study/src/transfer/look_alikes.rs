//! What analysts confuse with a wake (issue 38, item 3), drawn onto a rendered scene: ships
//! without a visible wake (anchored, or too slow to leave one), strong targets whose sidelobes
//! cross the scene, internal-wave packets, rain cells and current fronts. The slicks and
//! low-wind patches come from the surface model itself (`slicks`, `wind.variability`).
//!
//! Each feature changes the scene's mean backscatter, so it is applied to the speckled
//! intensity as a factor (speckle multiplies the mean), and a ship's return as its own
//! speckled target added to it. The shapes and their contrasts are approximate, chosen from
//! the ranges the cited observations report; none of them is simulated from its physics.

use ndarray::Array2;
use rand::{Rng, RngExt};
use rand_distr::{Distribution, Gamma};
use wakelab_core::units::RadarBand;
use wakelab_sensors::sar_image::skolnik_cross_section;

/// A ship whose return shows and whose wake does not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WakelessShip {
    /// Centre (pixels: row, column).
    pub centre: (f64, f64),
    pub length_m: f64,
    pub heading_deg: f64,
    /// Radar cross section (m^2).
    pub rcs: f64,
    /// Peak sidelobe of the impulse response below the peak (a factor): the bright cross a
    /// strong target draws along the image's rows and columns.
    pub sidelobe: f64,
}

impl WakelessShip {
    /// A ship of 20-250 m (log-uniform), beam a sixth and draught a fifteenth of its length,
    /// block coefficient 0.6: its displacement gives Skolnik's C-band cross section, times an
    /// aspect factor of 0 to -15 dB (a ship seen side-on returns far more than bow-on).
    fn draw(rng: &mut impl Rng, centre: (f64, f64)) -> Self {
        let length_m = (rng.random_range(20f64.ln()..250f64.ln())).exp();
        let kilotonnes = 0.6 * length_m * (length_m / 6.0) * (length_m / 15.0) * 1.025 / 1000.0;
        let aspect = 10f64.powf(-rng.random_range(0.0..1.5));
        Self {
            centre,
            length_m,
            heading_deg: rng.random_range(0.0..180.0),
            rcs: skolnik_cross_section(RadarBand::C, kilotonnes) * aspect,
            sidelobe: 10f64.powf(-rng.random_range(1.3..3.5)),
        }
    }

    /// Add the ship's return to `image` (linear intensity, pixels of `spacing` m): its cross
    /// section spread over the pixels its hull covers (sampled 4 x 4 per pixel), each pixel
    /// speckled as a `looks`-look target, and the sidelobes along its brightest pixel's row and
    /// column, falling as 1 / k^2 with the distance k in pixels (a sinc^2 envelope).
    fn draw_onto(&self, image: &mut Array2<f32>, spacing: f64, looks: u32, rng: &mut impl Rng) {
        let (rows, cols) = image.dim();
        let (sin, cos) = self.heading_deg.to_radians().sin_cos();
        let half = (0.5 * self.length_m / spacing, 0.5 * self.length_m / 6.0 / spacing);
        let reach = half.0.ceil() as isize + 1;
        let (r0, c0) = (self.centre.0.round() as isize, self.centre.1.round() as isize);
        let mut cover = Vec::new();
        for dr in -reach..=reach {
            for dc in -reach..=reach {
                let mut inside = 0;
                for (sr, sc) in (0..16).map(|k| ((k / 4) as f64, (k % 4) as f64)) {
                    let r = (r0 + dr) as f64 + (sr + 0.5) / 4.0 - 0.5 - self.centre.0;
                    let c = (c0 + dc) as f64 + (sc + 0.5) / 4.0 - 0.5 - self.centre.1;
                    let (along, across) = (r * cos + c * sin, -r * sin + c * cos);
                    inside += u32::from(along.abs() <= half.0 && across.abs() <= half.1.max(0.5));
                }
                if inside > 0 {
                    cover.push((r0 + dr, c0 + dc, inside as f64 / 16.0));
                }
            }
        }
        let total: f64 = cover.iter().map(|p| p.2).sum::<f64>().max(1e-9);
        let per_pixel = self.rcs / (spacing * spacing) / total;
        let speckle = Gamma::new(looks.max(1) as f64, 1.0 / looks.max(1) as f64).expect("positive looks");
        let mut brightest = (r0, c0, 0.0);
        for (r, c, share) in cover {
            if (0..rows as isize).contains(&r) && (0..cols as isize).contains(&c) {
                let v = per_pixel * share * speckle.sample(rng);
                image[[r as usize, c as usize]] += v as f32;
                if v > brightest.2 {
                    brightest = (r, c, v);
                }
            }
        }
        let (r, c, peak) = brightest;
        for k in 1..64isize {
            let v = (peak * self.sidelobe / (k * k) as f64) as f32;
            for (rr, cc) in [(r + k, c), (r - k, c), (r, c + k), (r, c - k)] {
                if (0..rows as isize).contains(&rr) && (0..cols as isize).contains(&cc) {
                    image[[rr as usize, cc as usize]] += v;
                }
            }
        }
    }
}

/// A target so bright (a large ship's superstructure, a platform, a corner reflector) that its
/// impulse response's sidelobes draw a straight bright line along the image's row and column
/// through it, kilometres long: a line with a bright point at its apex, as a wake's arm with its
/// ship. On real images these crosses, and grids of them through anchored ships, are among the
/// strongest alarms of wake detectors trained without them (docs/results.md, "Real wakes from
/// licensed images, and the shipped detectors"; trained with them, "Sidelobe crosses as
/// look-alikes, and a seed ensemble": no gain, so the embedded study leaves them out).
///
/// An unweighted rectangular aperture's response is sinc^2 along each axis (Cumming & Wong
/// 2005, Sec. 2.3): the first sidelobe 13.3 dB below the peak, the k-th peaking near
/// 1 / (pi (k + 1/2))^2; weighting lowers the near sidelobes (Taylor, Hamming: -25 to -40 dB)
/// while the far ones still fall as 1 / k^2. The line here is the peak times `sidelobe` / k^2
/// at k pixels (one pixel a resolution cell), and it shows as far as that stays above the sea.
/// That is approximate: from an unweighted first sidelobe it falls below sinc^2's envelope of
/// peaks by up to 3.3 dB within 60 pixels (the test measures it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrongTarget {
    /// The target's pixel (row, column).
    pub centre: (f64, f64),
    /// Its peak over the scene's mean intensity (dB).
    pub peak_db: f64,
    /// The first sidelobe below the peak (a factor).
    pub sidelobe: f64,
}

impl StrongTarget {
    /// Peaks 45-75 dB over the sea (a 10^5-10^7 m^2 target over 100 m^2 pixels of a sea at
    /// -20 dB), first sidelobes -13 to -35 dB: lines from a few pixels to the whole scene.
    fn draw(rng: &mut impl Rng, centre: (f64, f64)) -> Self {
        Self {
            centre,
            peak_db: rng.random_range(45.0..75.0),
            sidelobe: 10f64.powf(-rng.random_range(1.33..3.5)),
        }
    }

    /// Pixels from the target where its line falls to the sea's mean: sqrt(peak x sidelobe).
    pub fn line_reach(&self) -> f64 {
        (10f64.powf(self.peak_db / 10.0) * self.sidelobe).sqrt()
    }

    /// Add the target and its cross to `image`, whose mean intensity is `sea` (the response
    /// is deterministic: a point target's sidelobes carry no speckle of their own).
    fn draw_onto(&self, image: &mut Array2<f32>, sea: f64) {
        let (rows, cols) = image.dim();
        let (r, c) = (self.centre.0.round() as isize, self.centre.1.round() as isize);
        let peak = sea * 10f64.powf(self.peak_db / 10.0);
        let at = |image: &mut Array2<f32>, rr: isize, cc: isize, v: f64| {
            if (0..rows as isize).contains(&rr) && (0..cols as isize).contains(&cc) {
                image[[rr as usize, cc as usize]] += v as f32;
            }
        };
        at(image, r, c, peak);
        for k in 1..rows.max(cols) as isize {
            let v = peak * self.sidelobe / (k * k) as f64;
            for (rr, cc) in [(r + k, c), (r - k, c), (r, c + k), (r, c - k)] {
                at(image, rr, cc, v);
            }
        }
    }
}

/// A packet of internal solitary waves (Alpers 1985): the surface current converges ahead of
/// each crest and diverges behind it, roughening then smoothing the sea, so the SAR sees a
/// bright band beside a dark one along each crest. Crests are arcs of one circle; the leading
/// soliton is the strongest and the longest, those behind it weaker and closer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InternalWavePacket {
    /// The crests' centre of curvature (pixels) and the leading crest's radius (m).
    pub centre: (f64, f64),
    pub radius_m: f64,
    /// Solitons, the leading one's spacing to the next (m) and its contrast (dB, peak).
    pub solitons: usize,
    pub wavelength_m: f64,
    pub contrast_db: f64,
}

/// A rain cell over the sea (Alpers et al. 2016, C band): the downdraft's gust roughens a
/// disc of kilometres (brighter), and the rain itself may damp its core (darker).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RainCell {
    pub centre: (f64, f64),
    pub radius_m: f64,
    pub gust_db: f64,
    /// The core's change (dB, 0 or below) over 0.4 of the radius.
    pub core_db: f64,
}

/// A current front or shear line (Johannessen et al. 1996): a change of roughness across it,
/// and along it a thin line, dark where surfactants gather in the convergence, bright where
/// the waves steepen against the current.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Front {
    /// A point of the front (pixels) and its direction (degrees from the rows' axis).
    pub point: (f64, f64),
    pub direction_deg: f64,
    pub step_db: f64,
    pub line_db: f64,
    pub line_width_m: f64,
}

/// The look-alikes of one scene.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LookAlikes {
    pub ships: Vec<WakelessShip>,
    pub strong_targets: Vec<StrongTarget>,
    pub packets: Vec<InternalWavePacket>,
    pub rain_cells: Vec<RainCell>,
    pub fronts: Vec<Front>,
}

impl LookAlikes {
    /// The look-alikes of a square scene of `side` pixels of `spacing` m: `ships` ships
    /// without a wake anywhere in it, and an internal-wave packet, a rain cell and a front each
    /// with probability `chance`; then `strong` strong targets with their crosses.
    pub fn draw(rng: &mut impl Rng, side: usize, spacing: f64, ships: usize, chance: f64, strong: usize) -> Self {
        let s = side as f64;
        let ships = (0..ships)
            .map(|_| {
                let centre = (rng.random_range(0.0..s), rng.random_range(0.0..s));
                WakelessShip::draw(rng, centre)
            })
            .collect();
        let mut packets = Vec::new();
        if rng.random_bool(chance) {
            // the packet's leading crest crosses the scene: its centre of curvature lies a
            // radius away from a point in the scene
            let radius_m = rng.random_range(5_000.0..30_000.0);
            let through = (rng.random_range(0.2..0.8) * s, rng.random_range(0.2..0.8) * s);
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let r = radius_m / spacing;
            packets.push(InternalWavePacket {
                centre: (through.0 - r * angle.cos(), through.1 - r * angle.sin()),
                radius_m,
                solitons: rng.random_range(3..=8),
                wavelength_m: rng.random_range(200.0..800.0),
                contrast_db: rng.random_range(1.0..4.0),
            });
        }
        let mut rain_cells = Vec::new();
        if rng.random_bool(chance) {
            rain_cells.push(RainCell {
                centre: (rng.random_range(0.0..s), rng.random_range(0.0..s)),
                radius_m: rng.random_range(1_000.0..5_000.0),
                gust_db: rng.random_range(1.0..4.0),
                core_db: if rng.random_bool(0.5) {
                    -rng.random_range(1.0..4.0)
                } else {
                    0.0
                },
            });
        }
        let mut fronts = Vec::new();
        if rng.random_bool(chance) {
            fronts.push(Front {
                point: (rng.random_range(0.2..0.8) * s, rng.random_range(0.2..0.8) * s),
                direction_deg: rng.random_range(0.0..180.0),
                step_db: rng.random_range(-2.0..2.0),
                line_db: rng.random_range(1.0..3.0) * if rng.random_bool(0.5) { -1.0 } else { 1.0 },
                line_width_m: rng.random_range(20.0..80.0),
            });
        }
        let strong_targets = (0..strong)
            .map(|_| {
                let centre = (rng.random_range(0.0..s).floor(), rng.random_range(0.0..s).floor());
                StrongTarget::draw(rng, centre)
            })
            .collect();
        Self {
            ships,
            strong_targets,
            packets,
            rain_cells,
            fronts,
        }
    }

    /// The change (dB) of the sea's backscatter at pixel (`r`, `c`) from the packets, rain
    /// cells and fronts.
    pub fn decibels_at(&self, (r, c): (f64, f64), spacing: f64) -> f64 {
        let mut db = 0.0;
        for p in &self.packets {
            // metres behind the leading crest; each soliton a sech^2 of the current whose
            // derivative (convergence, then divergence) the roughness follows: the shape
            // -sech^2(x) tanh(x), whose peak is 0.385
            let behind = p.radius_m - (r - p.centre.0).hypot(c - p.centre.1) * spacing;
            let mut crest = 0.0;
            for n in 0..p.solitons {
                let shrink = 1.0 - 0.1 * n as f64;
                let width = 0.25 * p.wavelength_m * shrink;
                let x = (behind - crest) / width;
                if x.abs() < 8.0 {
                    let sech = 1.0 / x.cosh();
                    db += -p.contrast_db * shrink * sech * sech * x.tanh() / 0.385;
                }
                crest += p.wavelength_m * shrink;
            }
        }
        for cell in &self.rain_cells {
            let d = (r - cell.centre.0).hypot(c - cell.centre.1) * spacing / cell.radius_m;
            db += cell.gust_db * (-d * d).exp() + cell.core_db * (-(d / 0.4).powi(2)).exp();
        }
        for f in &self.fronts {
            let (sin, cos) = f.direction_deg.to_radians().sin_cos();
            let across = (-(r - f.point.0) * sin + (c - f.point.1) * cos) * spacing;
            db += 0.5 * f.step_db * (across / 100.0).tanh() + f.line_db * (-(across / f.line_width_m).powi(2)).exp();
        }
        db
    }

    /// `image` (linear intensity of a `looks`-look scene, pixels of `spacing` m, the sea's mean
    /// intensity `sea`, which sets the strong targets' peaks) with the look-alikes drawn onto it.
    pub fn apply(&self, image: &mut Array2<f32>, spacing: f64, looks: u32, sea: f64, rng: &mut impl Rng) {
        if !(self.packets.is_empty() && self.rain_cells.is_empty() && self.fronts.is_empty()) {
            image.indexed_iter_mut().for_each(|((r, c), v)| {
                *v *= 10f64.powf(self.decibels_at((r as f64, c as f64), spacing) / 10.0) as f32;
            });
        }
        for ship in &self.ships {
            ship.draw_onto(image, spacing, looks, rng);
        }
        for target in &self.strong_targets {
            target.draw_onto(image, sea);
        }
    }

    /// Points (pixels) on each look-alike inside a scene of `side` pixels where a window
    /// centred shows it: the ships, each strong target and a point of its cross a third of its
    /// reach (at most 60 pixels) away along the rows, a point of the leading crest and of the
    /// front, the rain cell's centre.
    pub fn anchors(&self, side: usize, spacing: f64) -> Vec<(f64, f64)> {
        let s = side as f64;
        let inside = |p: &(f64, f64)| (0.0..s).contains(&p.0) && (0.0..s).contains(&p.1);
        let mut points: Vec<(f64, f64)> = self.ships.iter().map(|ship| ship.centre).collect();
        for t in &self.strong_targets {
            points.push(t.centre);
            let along = (t.line_reach() / 3.0).clamp(1.0, 60.0);
            let beside = if t.centre.0 + along < s {
                t.centre.0 + along
            } else {
                t.centre.0 - along
            };
            points.push((beside, t.centre.1));
        }
        for p in &self.packets {
            // the crest's point nearest the scene's centre
            let (dr, dc) = (0.5 * s - p.centre.0, 0.5 * s - p.centre.1);
            let k = p.radius_m / spacing / dr.hypot(dc).max(1e-9);
            points.push((p.centre.0 + k * dr, p.centre.1 + k * dc));
        }
        points.extend(self.rain_cells.iter().map(|cell| cell.centre));
        points.extend(self.fronts.iter().map(|f| f.point));
        points.retain(inside);
        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// A ship's return on a dark sea holds its cross section (the speckle's mean is 1), and its
    /// sidelobe cross falls as 1 / k^2 along the row.
    #[test]
    fn a_wakeless_ship_returns_its_cross_section() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let ship = WakelessShip {
            centre: (100.0, 100.0),
            length_m: 120.0,
            heading_deg: 30.0,
            rcs: 1e4,
            sidelobe: 0.0,
        };
        let spacing = 10.0;
        let (mut sum, n) = (0.0, 200);
        for _ in 0..n {
            let mut image = Array2::zeros((200, 200));
            ship.draw_onto(&mut image, spacing, 4, &mut rng);
            sum += image.sum() as f64 * spacing * spacing;
        }
        let mean = sum / n as f64;
        assert!((mean / 1e4 - 1.0).abs() < 0.05, "{mean}");
        // Skolnik (1980): a 1 kt ship in C band (5.3 GHz) returns 52 sqrt(5300) = 3,786 m^2, and
        // 10 kt 10^1.5 times that
        assert!((skolnik_cross_section(RadarBand::C, 1.0) - 3785.7).abs() < 1.0);
        assert!((skolnik_cross_section(RadarBand::C, 10.0) / 3785.7 - 31.62).abs() < 0.02);
        let cross = WakelessShip {
            length_m: 5.0,
            sidelobe: 0.05,
            ..ship
        };
        let mut image = Array2::zeros((200, 200));
        cross.draw_onto(&mut image, spacing, 100, &mut rng);
        let ratio = image[[100, 110]] / image[[100, 120]];
        assert!((ratio - 4.0).abs() < 0.5, "{ratio}");
    }

    /// The k-th sidelobe's peak of the unweighted response sinc^2(x) = (sin(pi x) / (pi x))^2:
    /// its largest value for x in [k, k + 1], sampled every 1e-4 (analytic, apart from the
    /// code under test).
    fn sinc2_sidelobe(k: usize) -> f64 {
        (0..=10_000)
            .map(|i| {
                let x = k as f64 + i as f64 * 1e-4;
                let s = (std::f64::consts::PI * x).sin() / (std::f64::consts::PI * x);
                s * s
            })
            .fold(0.0, f64::max)
    }

    /// A strong target's cross, set at the unweighted sinc^2 response's first sidelobe: that is
    /// 13.26 dB below the peak (Cumming & Wong 2005 quote 13.3), its line follows sinc^2's
    /// sidelobe peaks within 3.6 dB, never above them, out to 60 pixels, along the row and the
    /// column only; it meets the sea's mean where `line_reach` says.
    #[test]
    fn a_strong_target_draws_its_cross_across_the_scene() {
        let first = sinc2_sidelobe(1);
        assert!((10.0 * first.log10() + 13.26).abs() < 0.01, "{first}");
        let target = StrongTarget {
            centre: (50.0, 200.0),
            peak_db: 60.0,
            sidelobe: first,
        };
        // a sea exact in f32, so that an untouched pixel adds exactly nothing
        let sea = 0.01f32 as f64;
        let mut image = Array2::from_elem((400, 400), sea as f32);
        target.draw_onto(&mut image, sea);
        let added = |r: usize, c: usize| image[[r, c]] as f64 - sea;
        for k in 1..=60 {
            let below = 10.0 * (sinc2_sidelobe(k) / (added(50, 200 + k) / added(50, 200))).log10();
            assert!((-1e-3..3.6).contains(&below), "sidelobe {k}: {below} dB under sinc^2's");
        }
        assert!((added(51, 200) / added(60, 200) - 100.0).abs() < 1e-2);
        // a 60 dB peak with a first sidelobe 10^-1.326 reaches 217.2 pixels: the line equals the
        // sea there, along the column to row 267 (along the row it is cut at the edge, 400)
        let reach = target.line_reach();
        assert!((reach - 217.2).abs() < 0.1, "{reach}");
        let at_reach = added(50 + reach.round() as usize, 200) / sea;
        assert!((at_reach - 1.0).abs() < 0.01, "{at_reach}");
        assert_eq!(added(51, 201), 0.0);
        assert_eq!(added(399, 399), 0.0);
    }

    /// The packet's solitons make bright and dark bands of the stated contrast at the leading
    /// crest, the rain cell its gust at its centre, the front its line and half its step on
    /// either side; the sea far from all of them is unchanged.
    #[test]
    fn the_extended_look_alikes_have_their_contrasts() {
        let spacing = 10.0;
        let packet = InternalWavePacket {
            centre: (0.0, -1000.0),
            radius_m: 15_000.0,
            solitons: 1,
            wavelength_m: 400.0,
            contrast_db: 3.0,
        };
        let only = LookAlikes {
            packets: vec![packet],
            ..LookAlikes::default()
        };
        // along row 0 the crest lies at column 500; sample across it
        let profile: Vec<f64> = (400..600).map(|c| only.decibels_at((0.0, c as f64), spacing)).collect();
        let (lo, hi) = profile
            .iter()
            .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert!((hi - 3.0).abs() < 0.05 && (lo + 3.0).abs() < 0.05, "{lo} {hi}");
        assert!(only.decibels_at((0.0, 100.0), spacing).abs() < 1e-3);
        let cell = LookAlikes {
            rain_cells: vec![RainCell {
                centre: (50.0, 50.0),
                radius_m: 2000.0,
                gust_db: 2.0,
                core_db: -3.0,
            }],
            ..LookAlikes::default()
        };
        assert!((cell.decibels_at((50.0, 50.0), spacing) + 1.0).abs() < 1e-9);
        assert!(cell.decibels_at((50.0, 2050.0), spacing).abs() < 1e-6);
        let front = LookAlikes {
            fronts: vec![Front {
                point: (100.0, 100.0),
                direction_deg: 0.0,
                step_db: 2.0,
                line_db: -2.0,
                line_width_m: 40.0,
            }],
            ..LookAlikes::default()
        };
        assert!((front.decibels_at((30.0, 100.0), spacing) + 2.0).abs() < 1e-9);
        assert!((front.decibels_at((30.0, 300.0), spacing) - 1.0).abs() < 1e-6);
        assert!((front.decibels_at((30.0, 0.0), spacing) + 1.0).abs() < 1e-6);
    }

    /// Every anchor of a drawn scene lies inside it, one per ship and feature there.
    #[test]
    fn the_anchors_lie_in_the_scene() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for _ in 0..20 {
            let l = LookAlikes::draw(&mut rng, 512, 10.0, 3, 1.0, 2);
            assert_eq!(
                (
                    l.ships.len(),
                    l.strong_targets.len(),
                    l.packets.len(),
                    l.rain_cells.len(),
                    l.fronts.len()
                ),
                (3, 2, 1, 1, 1)
            );
            let anchors = l.anchors(512, 10.0);
            assert!(anchors.len() >= 8, "{anchors:?}");
            assert!(anchors
                .iter()
                .all(|&(r, c)| (0.0..512.0).contains(&r) && (0.0..512.0).contains(&c)));
        }
    }
}
