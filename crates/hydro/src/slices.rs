//! Saved time slices of the wake and the 2D+t -> 3D transform x = U_ship t (Eqs. (2.24)-(2.25)).

use crate::solver::WakeSolver;
use crate::turbulence::eddy_viscosity;
use serde::Serialize;

/// A quantity saved for every slice, in output order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SliceField {
    U,
    V,
    W,
    K,
    Eps,
    NuT,
    DT,
    DS,
    RhoAnomaly,
}

impl SliceField {
    /// Every field, in the order of the slices' `fields` and of the NetCDF variables.
    pub const ALL: [SliceField; 9] = [
        SliceField::U,
        SliceField::V,
        SliceField::W,
        SliceField::K,
        SliceField::Eps,
        SliceField::NuT,
        SliceField::DT,
        SliceField::DS,
        SliceField::RhoAnomaly,
    ];

    /// The NetCDF variable's name, CF units and long name.
    pub const fn cf(self) -> (&'static str, &'static str, &'static str) {
        match self {
            SliceField::U => (
                "U",
                "m s-1",
                "axial (along-track) velocity, Earth frame, positive along the heading",
            ),
            SliceField::V => ("V", "m s-1", "cross-track velocity, positive to port"),
            SliceField::W => ("W", "m s-1", "vertical velocity, positive up"),
            SliceField::K => ("k", "m2 s-2", "turbulence kinetic energy"),
            SliceField::Eps => ("eps", "m2 s-3", "dissipation rate of turbulence kinetic energy"),
            SliceField::NuT => ("nu_t", "m2 s-1", "eddy viscosity"),
            SliceField::DT => ("dT", "K", "temperature perturbation from the background"),
            SliceField::DS => ("dS", "1e-3", "practical salinity perturbation from the background"),
            SliceField::RhoAnomaly => ("rho_anomaly", "kg m-3", "density perturbation from the background"),
        }
    }

    pub fn name(self) -> &'static str {
        self.cf().0
    }

    /// The CF standard name (CF standard name table, version 84), where the table has one: the
    /// track-frame velocities are the grid's x and y components; the perturbations and the
    /// eddy viscosity have none.
    pub const fn standard_name(self) -> Option<&'static str> {
        match self {
            SliceField::U => Some("sea_water_x_velocity"),
            SliceField::V => Some("sea_water_y_velocity"),
            SliceField::W => Some("upward_sea_water_velocity"),
            SliceField::K => Some("specific_turbulent_kinetic_energy_of_sea_water"),
            SliceField::Eps => Some("specific_turbulent_kinetic_energy_dissipation_in_sea_water"),
            SliceField::NuT | SliceField::DT | SliceField::DS | SliceField::RhoAnomaly => None,
        }
    }

    /// Position in a slice's `fields`.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// The saved quantities' (name, units, long name), in output order.
pub const SLICE_FIELDS: [(&str, &str, &str); 9] = {
    let mut out = [("", "", ""); 9];
    let mut i = 0;
    while i < 9 {
        out[i] = SliceField::ALL[i].cf();
        i += 1;
    }
    out
};

/// Every saved field at cell centres of one time (ny x nz each, z fastest), as f32.
#[derive(Debug, Clone, Serialize)]
pub struct CrossSection {
    pub time: f64,
    /// Fields in the order of [`SLICE_FIELDS`].
    pub fields: Vec<Vec<f32>>,
}

/// The top cell of every field at one time (ny values each).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SurfaceSlice {
    pub time: f64,
    /// Fields in the order of [`SLICE_FIELDS`].
    pub fields: Vec<Vec<f32>>,
}

impl SurfaceSlice {
    pub fn field(&self, field: SliceField) -> &[f32] {
        &self.fields[field.index()]
    }

    /// The slice at `time` between `self` and the later `next`, linear in time (the order of
    /// the Heun step, so saving a slice need not cut a time step short).
    pub fn interpolate(&self, next: &SurfaceSlice, time: f64) -> SurfaceSlice {
        let theta = time_fraction(self, next, time);
        let fields = self
            .fields
            .iter()
            .zip(&next.fields)
            .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x + theta * (y - x)).collect())
            .collect();
        SurfaceSlice { time, fields }
    }
}

/// Where `time` lies between slices `a` and `b`: 0 at a, 1 at b, clamped.
fn time_fraction(a: &SurfaceSlice, b: &SurfaceSlice, time: f64) -> f32 {
    let span = b.time - a.time;
    if span > 0.0 {
        ((time - a.time) / span).clamp(0.0, 1.0) as f32
    } else {
        0.0
    }
}

/// Centre values of every field, restricted to levels `levels`.
fn centre_fields(solver: &WakeSolver, levels: std::ops::Range<usize>) -> Vec<Vec<f32>> {
    let s = &solver.setup;
    let ny = s.ny;
    let nl = levels.len();
    let mut out = vec![Vec::with_capacity(ny * nl); SLICE_FIELDS.len()];
    let st = solver.state();
    for j in 0..ny {
        for kk in levels.clone() {
            let values = [
                st.u[[j, kk]],
                0.5 * (st.v[[j, kk]] + st.v[[j + 1, kk]]),
                0.5 * (st.w[[j, kk]] + st.w[[j, kk + 1]]),
                st.k[[j, kk]],
                st.eps[[j, kk]],
                eddy_viscosity(s, st.k[[j, kk]], st.eps[[j, kk]]),
                st.temperature[[j, kk]],
                st.salinity[[j, kk]],
                s.column
                    .density_anomaly(kk, st.temperature[[j, kk]], st.salinity[[j, kk]]),
            ];
            for (o, v) in out.iter_mut().zip(values) {
                o.push(v as f32);
            }
        }
    }
    out
}

impl WakeSolver {
    /// The full cross-section now.
    pub fn cross_section(&self) -> CrossSection {
        let nz = self.setup.nz;
        CrossSection {
            time: self.time(),
            fields: centre_fields(self, 0..nz),
        }
    }

    /// The surface (top cell) now.
    pub fn surface_slice(&self) -> SurfaceSlice {
        SurfaceSlice {
            time: self.time(),
            fields: centre_fields(self, 0..1),
        }
    }
}

/// The surface wake as a map over (x, y): x = U_ship t + x_IDP behind the stern (Eq. (2.24)),
/// linear interpolation between saved slices, y over the uniform core of the grid.
#[derive(Debug, Clone, Serialize)]
pub struct SurfaceMap {
    /// Distance behind the stern of each row (m).
    pub x: Vec<f64>,
    /// Cross-track position of each column (m).
    pub y: Vec<f64>,
    /// Fields in the order of [`SLICE_FIELDS`], each x-major (rows x, columns y).
    pub fields: Vec<Vec<f32>>,
}

impl SurfaceMap {
    /// Resample saved slices onto rows `dx` apart, columns `core` of the grid's y centres.
    pub fn from_slices(
        slices: &[SurfaceSlice],
        ship_speed: f64,
        x_idp: f64,
        y_centres: &[f64],
        core: std::ops::Range<usize>,
        dx: f64,
    ) -> Self {
        assert!(!slices.is_empty(), "a surface map needs at least one slice");
        let t_end = slices.last().expect("non-empty").time;
        let rows = ((ship_speed * t_end) / dx).floor() as usize + 1;
        let x: Vec<f64> = (0..rows).map(|r| x_idp + r as f64 * dx).collect();
        let y: Vec<f64> = y_centres[core.clone()].to_vec();
        let mut fields = vec![Vec::with_capacity(rows * y.len()); SLICE_FIELDS.len()];
        let mut seg = 0;
        for &xr in &x {
            let t = (xr - x_idp) / ship_speed;
            while seg + 2 < slices.len() && slices[seg + 1].time < t {
                seg += 1;
            }
            let (a, b) = if slices.len() == 1 {
                (&slices[0], &slices[0])
            } else {
                (&slices[seg], &slices[seg + 1])
            };
            let f = time_fraction(a, b, t);
            for (out, (fa, fb)) in fields.iter_mut().zip(a.fields.iter().zip(&b.fields)) {
                out.extend(core.clone().map(|j| fa[j] * (1.0 - f) + fb[j] * f));
            }
        }
        Self { x, y, fields }
    }

    pub fn field(&self, field: SliceField) -> &[f32] {
        &self.fields[field.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slice_between_steps_is_linear_in_time() {
        let slice = |t: f64, v: f32| SurfaceSlice {
            time: t,
            fields: vec![vec![v, 2.0 * v]; SLICE_FIELDS.len()],
        };
        let (a, b) = (slice(10.0, 1.0), slice(14.0, 3.0));
        let mid = a.interpolate(&b, 11.0);
        assert_eq!(mid.time, 11.0);
        assert_eq!(mid.fields[0], vec![1.5, 3.0]);
        assert_eq!(a.interpolate(&b, 14.0).fields[4], b.fields[4]);
        assert_eq!(a.interpolate(&b, 10.0).fields[4], a.fields[4]);
    }

    #[test]
    fn map_interpolates_linearly_in_time_at_x_equal_u_t() {
        let slice = |t: f64, v: f32| SurfaceSlice {
            time: t,
            fields: vec![vec![v; 3]; SLICE_FIELDS.len()],
        };
        let slices = [slice(0.0, 0.0), slice(10.0, 1.0), slice(20.0, 3.0)];
        let map = SurfaceMap::from_slices(&slices, 7.0, 71.0, &[-1.0, 0.0, 1.0], 0..3, 35.0);
        // rows at t = 0, 5, 10, 15, 20 s
        assert_eq!(map.x.len(), 5);
        let u = map.field(SliceField::U);
        let want = [0.0, 0.5, 1.0, 2.0, 3.0];
        for (r, w) in want.iter().enumerate() {
            assert!((u[r * 3 + 1] - w).abs() < 1e-6, "row {r}: {}", u[r * 3 + 1]);
        }
        assert!((map.x[2] - (71.0 + 70.0)).abs() < 1e-12);
    }
}
