//! The search space: the gait parameters a study may vary, their bounds and the map to the
//! unit cube.

use super::*;

/// One of the gait parameters the optimiser may vary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Param {
    /// `gait.stress`, the muscle stress `Gamma` (Pa).
    Stress,
    /// `gait.sigma`, the couple width (fraction of L).
    Sigma,
    /// `gait.speed`, the travelling speed `v_m` (m/s).
    Speed,
    /// `gait.period`, the launch period of a sidewinding gait (s).
    Period,
    /// The triplet's spacing `b - a = c - b` (fraction of L): `gait.centers` becomes
    /// `[a, a + spacing, a + 2 spacing]` with the base file's first centre `a`.
    Spacing,
    /// `gait.scales[1]`, the scale of the out-of-plane couple `b` (the lift).
    Lift,
}

impl Param {
    /// All of them, in column order.
    pub const ALL: [Param; 6] = [
        Param::Stress,
        Param::Sigma,
        Param::Speed,
        Param::Period,
        Param::Spacing,
        Param::Lift,
    ];

    /// Key in `[optimize]` (and of `[gait]` for stress, sigma, speed and period).
    pub fn key(self) -> &'static str {
        match self {
            Param::Stress => "stress",
            Param::Sigma => "sigma",
            Param::Speed => "speed",
            Param::Period => "period",
            Param::Spacing => "spacing",
            Param::Lift => "lift",
        }
    }

    /// Unit, as written in messages.
    pub fn unit(self) -> &'static str {
        match self {
            Param::Stress => "Pa",
            Param::Sigma | Param::Spacing => "fraction of rod.length",
            Param::Speed => "m/s",
            Param::Period => "s",
            Param::Lift => "scale of the out-of-plane couple, gait.scales[1]",
        }
    }

    pub(super) fn get(self, p: &GaitParams) -> f64 {
        match self {
            Param::Stress => p.stress,
            Param::Sigma => p.sigma,
            Param::Speed => p.speed,
            Param::Period => p.period,
            Param::Spacing => p.spacing,
            Param::Lift => p.lift,
        }
    }

    pub(super) fn set(self, p: &mut GaitParams, v: f64) {
        match self {
            Param::Stress => p.stress = v,
            Param::Sigma => p.sigma = v,
            Param::Speed => p.speed = v,
            Param::Period => p.period = v,
            Param::Spacing => p.spacing = v,
            Param::Lift => p.lift = v,
        }
    }

    /// Whether `[lo, hi]` are allowed bounds of this parameter on `base`; `Err` holds what is
    /// allowed (for the message naming `optimize.<key>`).
    pub(super) fn check_bounds(self, base: &Problem, lo: f64, hi: f64) -> Result<(), String> {
        let unit = self.unit();
        let kind = base.gait.kind;
        let gaussian = matches!(kind, gait::Kind::SStart | gait::Kind::Sidewinding);
        let finite = lo.is_finite() && hi.is_finite() && lo < hi;
        match self {
            Param::Stress if !(finite && lo >= 0.0) => {
                Err(format!("[lo, hi] with 0 <= lo < hi, finite ({unit})"))
            }
            Param::Sigma => {
                // The Gaussian gaits need at least one element of the base mesh (a narrower
                // Gaussian falls between the nodes and the muscles do nothing).
                let min = 1.0 / base.rod.elements as f64;
                if !(lo > 0.0 && lo < hi && hi <= 1.0 && (!gaussian || lo >= min)) {
                    Err(if gaussian {
                        format!("[lo, hi] with 0 < lo < hi <= 1 and lo at least one element, 1/rod.elements = {min} ({unit})")
                    } else {
                        format!("[lo, hi] with 0 < lo < hi <= 1 ({unit})")
                    })
                } else if kind == gait::Kind::Serpenoid {
                    // A variable the base's gait does not use would "converge" at once.
                    Err("absent for a base whose gait is \"serpenoid\": its travelling curvature wave has no width sigma (it has gait.wavelength), so sigma changes nothing".into())
                } else {
                    Ok(())
                }
            }
            Param::Speed if !(finite && lo > 0.0) => {
                Err(format!("[lo, hi] with 0 < lo < hi, finite ({unit})"))
            }
            Param::Period if kind != gait::Kind::Sidewinding => Err(
                "absent unless the base's gait is \"sidewinding\" (only sidewinding launches triplets periodically)".into(),
            ),
            Param::Period if !(finite && lo > 0.0) => {
                Err(format!("[lo, hi] with 0 < lo < hi, finite ({unit})"))
            }
            Param::Spacing | Param::Lift if !gaussian => Err(format!(
                "absent unless the base's gait is \"s-start\" or \"sidewinding\" (the {} belongs to their triplet of couples)",
                if self == Param::Lift { "lift" } else { "spacing" }
            )),
            Param::Spacing => {
                let [a, b, c] = base.gait.centers;
                if ((c - b) - (b - a)).abs() > 1e-9 {
                    return Err(format!(
                        "absent for a base whose gait.centers = [{a}, {b}, {c}] are not evenly spaced (the spacing sets them to [a, a + spacing, a + 2 spacing])"
                    ));
                }
                if !(finite && lo > 0.0 && a + 2.0 * hi <= 1.0) {
                    return Err(format!(
                        "[lo, hi] with 0 < lo < hi and gait.centers[0] + 2 hi = {a} + 2 hi <= 1, finite ({unit}), so the centres stay on the body"
                    ));
                }
                Ok(())
            }
            Param::Lift if !finite => Err(format!("[lo, hi] with lo < hi, finite ({unit})")),
            _ => Ok(()),
        }
    }
}

/// Gait parameters of one evaluation (physical units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GaitParams {
    /// Muscle stress `Gamma` (Pa).
    pub stress: f64,
    /// Couple width `sigma` (fraction of L).
    pub sigma: f64,
    /// Travelling speed `v_m` (m/s).
    pub speed: f64,
    /// Launch period (s): `gait.period` (used by sidewinding only).
    pub period: f64,
    /// The triplet's spacing `centers[1] - centers[0]` (fraction of L).
    pub spacing: f64,
    /// The out-of-plane couple's scale `scales[1]`.
    pub lift: f64,
}

impl GaitParams {
    /// The gait values of a problem file.
    pub fn of(base: &Problem) -> GaitParams {
        let g = &base.gait;
        GaitParams {
            stress: g.stress,
            sigma: g.sigma,
            speed: g.speed,
            period: g.period,
            spacing: g.centers[1] - g.centers[0],
            lift: g.scales[1],
        }
    }
}

/// One optimised dimension: bounds and starting value (physical units).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Dim {
    /// Which parameter.
    pub param: Param,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound (> `lo`).
    pub hi: f64,
    /// Starting value, in `[lo, hi]`.
    pub initial: f64,
}

/// The search space: the optimised dimensions and the fixed values of the others.
#[derive(Clone, Debug)]
pub struct Space {
    /// Optimised dimensions, in the order of [`Param::ALL`] (those present).
    pub dims: Vec<Dim>,
    /// Values of every parameter when not optimised (the base problem's).
    pub fixed: GaitParams,
}

impl Space {
    /// Normalised coordinates `u_i = (x_i - lo_i) / (hi_i - lo_i)` of a physical point.
    pub fn to_unit(&self, p: &GaitParams) -> Vec<f64> {
        self.dims
            .iter()
            .map(|d| (d.param.get(p) - d.lo) / (d.hi - d.lo))
            .collect()
    }

    /// The physical point of normalised coordinates `u`, clamped to the bounds, and the
    /// Euclidean distance of `u` from the unit cube (0 inside). Non-finite coordinates clamp
    /// to the lower bound at infinite distance.
    pub fn point(&self, u: &[f64]) -> (GaitParams, f64) {
        let mut p = self.fixed;
        let mut d2 = 0.0;
        for (d, &ui) in self.dims.iter().zip(u) {
            let (c, out) = if ui.is_nan() {
                (0.0, f64::INFINITY)
            } else {
                let c = ui.clamp(0.0, 1.0);
                (c, ui - c)
            };
            d2 += out * out;
            // Exact bounds at the cube's faces (no round-off past lo or hi).
            let x = if c <= 0.0 {
                d.lo
            } else if c >= 1.0 {
                d.hi
            } else {
                (d.lo + c * (d.hi - d.lo)).clamp(d.lo, d.hi)
            };
            d.param.set(&mut p, x);
        }
        (p, d2.sqrt())
    }

    /// The point as written in log lines: stress, sigma and speed, then every other optimised
    /// parameter ("stress 23500 Pa, sigma 0.044, speed 0.25 m/s, period 1.8 s").
    pub fn describe(&self, p: &GaitParams) -> String {
        let mut s = format!(
            "stress {} Pa, sigma {}, speed {} m/s",
            p.stress, p.sigma, p.speed
        );
        for d in &self.dims {
            match d.param {
                Param::Period => s += &format!(", period {} s", p.period),
                Param::Spacing => s += &format!(", spacing {}", p.spacing),
                Param::Lift => s += &format!(", lift {}", p.lift),
                _ => {}
            }
        }
        s
    }

    /// Whether `param` is optimised.
    pub fn varies(&self, param: Param) -> bool {
        self.dims.iter().any(|d| d.param == param)
    }

    /// The starting point (physical).
    pub fn initial(&self) -> GaitParams {
        let mut p = self.fixed;
        for d in &self.dims {
            d.param.set(&mut p, d.initial);
        }
        p
    }

    /// The initial simplex in normalised coordinates: the starting point and, for each
    /// dimension, the starting point moved by `step` along it (backward where forward would
    /// leave the unit cube).
    pub fn initial_simplex(&self, step: f64) -> Vec<Vec<f64>> {
        self.simplex_at(self.to_unit(&self.initial()), step)
    }

    /// The simplex of [`Space::initial_simplex`] around the normalised point `u0`.
    pub fn simplex_at(&self, u0: Vec<f64>, step: f64) -> Vec<Vec<f64>> {
        let mut simplex = vec![u0.clone()];
        for i in 0..u0.len() {
            let mut v = u0.clone();
            v[i] = if u0[i] + step <= 1.0 {
                u0[i] + step
            } else {
                u0[i] - step
            };
            simplex.push(v);
        }
        simplex
    }
}
