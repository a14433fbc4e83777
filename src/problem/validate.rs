//! Validation of a parsed problem: each key against its range ([`keys`]), then the rules that
//! involve several keys, then the derived quantities ([`super::derived`]); every error names the
//! file, the key, its line and what is allowed.

use super::*;

pub(super) struct Checker<'a> {
    text: &'a str,
    path: &'a Path,
}

impl Checker<'_> {
    /// `v` within `k`'s range, or the error naming `k` and its allowed values.
    pub(super) fn key(&self, k: &keys::Key, v: f64) -> Result<(), ProblemError> {
        if k.check_real(v) {
            Ok(())
        } else {
            Err(self.fail_key(k, num(v)))
        }
    }
    /// Every entry of `v` finite (array keys), or the error naming `k`.
    pub(super) fn key_finite(&self, k: &keys::Key, v: &[f64]) -> Result<(), ProblemError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(self.fail_key(k, format!("{v:?}")))
        }
    }
    /// Integer `v` within `k`'s range, or the error naming `k`.
    pub(super) fn int(&self, k: &keys::Key, v: usize) -> Result<(), ProblemError> {
        if k.check_int(v as u64) {
            Ok(())
        } else {
            Err(self.fail_key(k, format!("{v}")))
        }
    }
    pub(super) fn fail_key(&self, k: &keys::Key, value: String) -> ProblemError {
        let (table, key) = k.key.split_once('.').expect("dotted key");
        self.fail(table, key, value, &k.allowed())
    }
    pub(super) fn fail(
        &self,
        table: &str,
        key: &str,
        value: String,
        allowed: &str,
    ) -> ProblemError {
        ProblemError::Invalid {
            file: self.path.into(),
            line: key_line(self.text, table, key),
            key: format!("{table}.{key}"),
            value,
            allowed: allowed.into(),
        }
    }
}

pub(super) fn validate(p: &Problem, text: &str, path: &Path) -> Result<(), ProblemError> {
    use keys::*;
    ranges::check_lengths(text, path)?;
    let c = Checker { text, path };
    let r = &p.rod;
    c.key(&ROD_LENGTH, r.length)?;
    c.key(&ROD_DIAMETER, r.diameter)?;
    if r.diameter >= r.length {
        return Err(c.fail_key(&ROD_DIAMETER, num(r.diameter)));
    }
    c.int(&ROD_ELEMENTS, r.elements)?;
    c.key(&ROD_DENSITY, r.density)?;
    c.key(&ROD_BENDING_STIFFNESS, r.bending_stiffness)?;
    if let Some(v) = r.twist_stiffness {
        c.key(&ROD_TWIST_STIFFNESS, v)?;
    }
    if let Some(v) = r.stretch_stiffness {
        c.key(&ROD_STRETCH_STIFFNESS, v)?;
    }
    c.key(&ROD_DAMPING_TIME, r.damping_time)?;
    c.key_finite(&ROD_NATURAL_CURVATURE, &r.natural_curvature)?;
    c.key(&ROD_NATURAL_TWIST, r.natural_twist)?;
    initial::check(p, &c)?;
    c.key(&GRAVITY_G, p.gravity.g)?;
    let t = &p.time;
    match t.mode {
        Mode::Dynamic => {
            let dt = t.dt.ok_or_else(|| {
                c.fail(
                    "time",
                    "dt",
                    "(missing)".into(),
                    "given in dynamic mode, > 0 (s)",
                )
            })?;
            c.key(&TIME_DT, dt)?;
            let d = t.duration.ok_or_else(|| {
                c.fail(
                    "time",
                    "duration",
                    "(missing)".into(),
                    "given in dynamic mode, > 0 (s)",
                )
            })?;
            c.key(&TIME_DURATION, d)?;
            if dt > d {
                return Err(c.fail("time", "dt", num(dt), "at most time.duration (s)"));
            }
        }
        Mode::Static => {
            if r.clamp == Clamp::None {
                return Err(c.fail("time", "mode", "\"static\"".into(), "\"dynamic\" unless rod.clamp is \"head\" or \"tail\" (a free rod has no static equilibrium)"));
            }
            if let Some(dt) = t.dt {
                c.key(&TIME_DT, dt)?;
            }
            if let Some(d) = t.duration {
                c.key(&TIME_DURATION, d)?;
            }
        }
    }
    time::check(p, &c)?;
    if let Some(a) = &p.accuracy {
        if let Err((key, value, allowed)) = check_accuracy(a, p) {
            return Err(c.fail("accuracy", key, value, &allowed));
        }
    }
    c.int(&TIME_LOAD_STEPS, t.load_steps)?;
    ground::check(p, &c)?;
    self_contact::check_keys(p, &c)?;
    let g = &p.gait;
    c.key(&GAIT_STRESS, g.stress)?;
    c.key(&GAIT_SIGMA, g.sigma)?;
    c.key(&GAIT_SPEED, g.speed)?;
    c.key_finite(&GAIT_CENTERS, &g.centers)?;
    // The couples' centres and width matter for the Gaussian gaits: a centre off the body or a
    // width below one element (a Gaussian that falls between the nodes) runs without muscle
    // action.
    if matches!(g.kind, Kind::SStart | Kind::Sidewinding) {
        if !g.centers.iter().all(|x| (0.0..=1.0).contains(x)) {
            return Err(c.fail_key(&GAIT_CENTERS, format!("{:?}", g.centers)));
        }
        let min_sigma = 1.0 / r.elements as f64;
        if g.sigma < min_sigma {
            return Err(c.fail(
                "gait",
                "sigma",
                num(g.sigma),
                &format!(
                    "at least one element length, 1/rod.elements = {min_sigma} (fraction of rod.length), and at most 1"
                ),
            ));
        }
    }
    c.key_finite(&GAIT_SCALES, &g.scales)?;
    c.key(&GAIT_PERIOD, g.period)?;
    c.key(&GAIT_RAMP, g.ramp)?;
    c.key(&GAIT_WAVELENGTH, g.wavelength)?;
    if let Some(iv) = p.output.interval {
        c.key(&OUTPUT_INTERVAL, iv)?;
    }
    if p.solver.integrator == IntegratorKind::VelocityVerlet {
        if p.ground.is_some() {
            return Err(c.fail(
                "solver",
                "integrator",
                "\"explicit\"".into(),
                "\"implicit\" or \"bdf2\" when a [ground] is present (the explicit integrator has no contact)",
            ));
        }
        if t.mode == Mode::Static {
            return Err(c.fail(
                "solver",
                "integrator",
                "\"explicit\"".into(),
                "\"implicit\" in static mode (the explicit integrator only steps in time)",
            ));
        }
        if p.rod.damping_time > 0.0 {
            return Err(c.fail(
                "solver",
                "integrator",
                "\"explicit\"".into(),
                "\"implicit\" or \"bdf2\" when rod.damping_time > 0 (rod damping is implicit)",
            ));
        }
    }
    if p.solver.integrator == IntegratorKind::Bdf2 && t.mode == Mode::Static {
        return Err(c.fail(
            "solver",
            "integrator",
            "\"bdf2\"".into(),
            "\"implicit\" in static mode (BDF2 only steps in time)",
        ));
    }
    if let Err((k, value)) = p.solver.check_settings() {
        return Err(c.fail_key(k, value));
    }
    if let Err(allowed) = solver::check_clarabel_method(&p.solver.clarabel_method) {
        return Err(c.fail(
            "solver",
            "clarabel_method",
            format!("{:?}", p.solver.clarabel_method),
            allowed,
        ));
    }
    derived::check(p, &c)
}
