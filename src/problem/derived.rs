//! Quantities derived from several keys, checked after each key is in its own range.
//!
//! Every key may be finite and positive while a product of keys overflows: `density = 1e308`
//! gives an infinite node mass and scaled weight, `gait.stress = 1e308` an infinite natural
//! curvature whose bending energy overflows at the first Newton iterate. Such a run used to
//! start and fail with "non-finite objective" (or finish with `scaled_weight: null`). Each
//! quantity below must lie within `[1/DERIVED_LIMIT, DERIVED_LIMIT]` in magnitude (its SI
//! value): the step objective multiplies and squares them, and a margin of 1e100 keeps every
//! such product finite. The error names the key of the quantity whose value is furthest from
//! 1 in orders of magnitude (the one to fix), the quantity and its value. Every bundled
//! problem is within 1e-12..1e7.
//!
//! The quantities: node mass `rho A L/N`, twist inertia `rho J L/N`, bending, twist and
//! stretch stiffness per element (`B N/L`, `C N/L`, `EA`), the inertia of a step
//! `rho A (L/N) / dt^2`, with gravity the node weight `rho A (L/N) g` and the scaled weight
//! `W = rho g a^2 L^3 / B`, and with a gait the couple `Gamma a^3`, the curvature it imposes
//! `Gamma a^3 / B`, its bending energy `(Gamma a^3)^2 L / B`, the scaled torque
//! `G = Gamma a^3 L / B` and the pulse time `L / v_m`.

use super::{Checker, Kind, Problem, ProblemError};
use std::f64::consts::PI;

/// Largest allowed magnitude of a derived quantity (and the inverse of the smallest).
pub const DERIVED_LIMIT: f64 = 1e100;

/// A derived quantity: its name, value, unit and the keys it depends on with their values.
type Quantity = (&'static str, f64, &'static str, Vec<(&'static str, f64)>);

/// Check the derived quantities of a problem whose keys are each valid.
pub(super) fn check(p: &Problem, c: &Checker) -> Result<(), ProblemError> {
    let r = &p.rod;
    let (rho, a, len, b) = (r.density, r.diameter, r.length, r.bending_stiffness);
    let n = r.elements as f64;
    let area = PI * a * a / 4.0;
    let polar = PI * a.powi(4) / 32.0;
    let l = len / n;
    let twist = r.twist_stiffness.unwrap_or(2.0 * b / 3.0);
    let stretch = r.stretch_stiffness.unwrap_or(16.0 * b / (a * a));
    let g = p.gravity.g;
    let dt = p.time.dt.unwrap_or(1.0);
    let key = |k: &'static str, v: f64| (k, v);
    let (k_rho, k_a, k_len, k_b, k_n) = (
        key("rod.density", rho),
        key("rod.diameter", a),
        key("rod.length", len),
        key("rod.bending_stiffness", b),
        key("rod.elements", n),
    );
    let mut quantities: Vec<Quantity> = vec![
        (
            "node mass rho A L/N",
            rho * area * l,
            "kg",
            vec![k_rho, k_a, k_len, k_n],
        ),
        (
            "twist inertia rho J L/N",
            rho * polar * l,
            "kg m^2",
            vec![k_rho, k_a, k_len, k_n],
        ),
        (
            "bending stiffness per element B N/L",
            b / l,
            "N m",
            vec![k_b, k_len, k_n],
        ),
        (
            "twist stiffness per element C N/L",
            twist / l,
            "N m",
            vec![key("rod.twist_stiffness", twist), k_len, k_n],
        ),
        (
            "stretch stiffness EA",
            stretch,
            "N",
            vec![key("rod.stretch_stiffness", stretch), k_b, k_a],
        ),
        (
            "step inertia rho A (L/N) / dt^2",
            rho * area * l / (dt * dt),
            "kg/s^2",
            vec![k_rho, k_a, k_len, k_n, key("time.dt", dt)],
        ),
    ];
    if g > 0.0 {
        let k_g = key("gravity.g", g);
        quantities.push((
            "node weight rho A (L/N) g",
            rho * area * l * g,
            "N",
            vec![k_rho, k_a, k_len, k_n, k_g],
        ));
        quantities.push((
            "scaled weight W = rho g a^2 L^3 / B",
            rho * g * a * a * len.powi(3) / b,
            "dimensionless",
            vec![k_rho, k_g, k_a, k_len, k_b],
        ));
    }
    let gait = &p.gait;
    // The largest couple: `gait.scales` multiply `Gamma a^3` (`scales = [1e300, 1, 1]` used to
    // pass and overflow in the first step).
    let scale = gait.scales.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    if gait.kind != Kind::None && gait.stress * scale > 0.0 {
        let k_s = key("gait.stress", gait.stress);
        let couple = gait.stress * a.powi(3) * scale.max(1.0);
        quantities.extend([
            (
                "largest muscle couple Gamma a^3 max(1, |scales|)",
                couple,
                "N m",
                vec![k_s, k_a, key("gait.scales", scale)],
            ),
            (
                "imposed curvature Gamma a^3 / B",
                couple / b,
                "1/m",
                vec![k_s, k_a, k_b],
            ),
            (
                "muscle bending energy (Gamma a^3)^2 L / B",
                couple * couple * len / b,
                "J",
                vec![k_s, k_a, k_len, k_b],
            ),
            (
                "scaled torque G = Gamma a^3 L / B",
                couple * len / b,
                "dimensionless",
                vec![k_s, k_a, k_len, k_b],
            ),
            (
                "pulse time L / v_m",
                len / gait.speed,
                "s",
                vec![k_len, key("gait.speed", gait.speed)],
            ),
        ]);
    }
    for (what, v, unit, keys) in quantities {
        let m = v.abs();
        if m.is_finite() && (1.0 / DERIVED_LIMIT..=DERIVED_LIMIT).contains(&m) {
            continue;
        }
        // The key furthest from 1 in orders of magnitude is the one to fix.
        let (k, kv) = keys
            .iter()
            .copied()
            .max_by(|x, y| x.1.abs().log10().abs().total_cmp(&y.1.abs().log10().abs()))
            .unwrap_or(("rod.density", rho));
        let (table, name) = k.split_once('.').unwrap_or(("rod", k));
        return Err(c.fail(
            table,
            name,
            super::num(kv),
            &format!(
                "a value for which the {what} stays within 1e-100..1e100 ({unit}); it is {v:.3e}"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::num;

    #[test]
    fn numbers_print_short_and_read_back_exactly() {
        for (v, text) in [
            (1e308, "1e308"),
            (-3.0, "-3"),
            (0.0, "0"),
            (2.5e-4, "0.00025"),
            (1e-5, "1e-5"),
            (24525.0, "24525"),
            (1.0e7, "1e7"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(num(v), text);
        }
        for v in [
            0.1,
            1.0 / 3.0,
            6.02e23,
            1.7e-300,
            9_999_999.5,
            f64::MAX,
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(num(v).parse::<f64>().unwrap().to_bits(), v.to_bits(), "{v}");
        }
    }
}
