//! The status changes of an active-set step ([`super::Step`]): the exact Coulomb conditions
//! at a converged point, slip fronts, and the early changes taken while Newton iterates
//! (lift-offs, slides, reversals and landings). Split from `active.rs` to keep each file to
//! one job; the constants that tune them live with the step ([`super::FRONT_ROUNDS`] and
//! the others).

use super::*;

impl Step<'_, '_> {
    /// Exact Coulomb conditions at a converged point; a contact that violates them changes
    /// status (pulling: lifts off; friction outside the cone: slides in the direction its
    /// force dictates) and Newton continues. Returns the number of changes (0: converged).
    pub(super) fn converged_switches(&mut self, q: &mut [f64]) -> Result<usize, ContactFailure> {
        let (m, force_tol) = (self.m, self.m.solver.contact_force_tolerance);
        let (ct, st, s) = (&mut *self.ct, &mut *self.st, &mut *self.s);
        let mut switched = 0;
        s.slid.clear();
        for c in 0..ct.nodes.len() {
            if st.mode[c] != Mode::Free && st.react[c] < -force_tol * self.scale {
                log::debug!("  switch conv-lift {c}");
                self.stats.switches.converged_lifts += 1;
                st.set(ct, m, c, Mode::Free, q, &mut s.held);
                switched += 1;
            } else if st.mode[c] == Mode::Stick && st.ratio[c] > 1.0 + force_tol {
                log::debug!("  switch conv-slide {c}");
                self.stats.switches.converged_slides += 1;
                st.set(ct, m, c, Mode::Slide, q, &mut s.held);
                s.slid.push(c);
                switched += 1;
            }
        }
        // A slip front: FRONT_ROUNDS converged points in a row where a contact left the cone.
        if s.slid.is_empty() {
            s.conv_slide_rounds = 0;
        } else {
            s.conv_slide_rounds += 1;
        }
        if s.conv_slide_rounds >= FRONT_ROUNDS {
            switched += self.front_slides(q);
        }
        if switched > 0 {
            self.count_switches(switched)?;
        }
        Ok(switched)
    }

    /// At a slip front, sticking neighbours of the contacts that slid, contiguous with them
    /// and within FRONT_MARGIN of the cone, slide too (a wrong guess reverses and sticks again
    /// in the next iterate; the exact conditions are still verified at the converged point).
    /// Returns the number of changes.
    pub(super) fn front_slides(&mut self, q: &mut [f64]) -> usize {
        let (ct, st, s) = (&mut *self.ct, &mut *self.st, &mut *self.s);
        let nc = ct.nodes.len();
        let mut switched = 0;
        for &c0 in s.slid.iter() {
            // Walk to either side along neighbouring nodes.
            for step in [usize::checked_sub, usize::checked_add] {
                let mut prev = c0;
                while let Some(c) = step(prev, 1).filter(|&c| c < nc) {
                    if ct.nodes[c].abs_diff(ct.nodes[prev]) != 1
                        || st.mode[c] != Mode::Stick
                        || st.ratio[c] <= 1.0 - FRONT_MARGIN
                    {
                        break;
                    }
                    log::debug!("  switch front-slide {c}");
                    self.stats.switches.front_slides += 1;
                    st.set(ct, self.m, c, Mode::Slide, q, &mut s.held);
                    switched += 1;
                    prev = c;
                }
            }
        }
        switched
    }

    /// Status changes before convergence. A contact pulling now and after the step lifts
    /// off; a sticking force outside the cone now and after the step slides (see
    /// [`super::reactions`]). Those release coordinates the direction held fixed (a lift-off
    /// its height, a new slide its ground position), so the direction is still one of descent
    /// with the new statuses: it is taken rather than thrown away. A sliding contact whose
    /// full step reverses its slip stops (sticks); a free contact that the full step takes
    /// below the ground lands. Their coordinates move onto the new constraints and the rest of
    /// the step is taken if it still descends on the merit, else the direction is recomputed
    /// ([`Next::Again`]): recomputing it after every reversal cost 4.20 against 4.03 it/step
    /// on the 200-element S-start (2 front rounds), 54 % of the reversed contacts sliding on
    /// in their first direction by the step's end.
    pub(super) fn early_switches(
        &mut self,
        q: &mut [f64],
        at: &mut Assembled,
    ) -> Result<Next, ContactFailure> {
        let released = self.early_releases(q);
        let held_now = self.reversals_and_landings(q);
        let switched = released + held_now;
        if switched == 0 {
            return Ok(Next::Go);
        }
        self.count_switches(switched)?;
        if held_now > 0 {
            // The step without its components at the newly held coordinates (which moved onto
            // their constraints), if it still descends; otherwise a new direction.
            for (d, &h) in self.nw.dq.iter_mut().zip(&self.s.held) {
                if h {
                    *d = 0.0;
                }
            }
            let slope: f64 = self
                .nw
                .asm
                .grad
                .iter()
                .zip(&self.nw.dq)
                .map(|(g, d)| g * d)
                .sum();
            if slope >= 0.0 {
                return Ok(Next::Again);
            }
        }
        // The merit with the new statuses at the (slightly moved) start point.
        at.f0 = self.obj.value(q) + self.ct.dissipation(self.ground, q);
        Ok(Next::Go)
    }

    /// Early lift-offs and slides (once per contact and step); returns their number.
    pub(super) fn early_releases(&mut self, q: &mut [f64]) -> usize {
        let (m, force_tol) = (self.m, self.m.solver.contact_force_tolerance);
        let (ct, st, s) = (&mut *self.ct, &mut *self.st, &mut *self.s);
        let mut switched = 0;
        let pull = -force_tol * self.scale;
        for c in 0..ct.nodes.len() {
            let ch = s.reactions.change[c];
            if s.early[c] >= EARLY_CHANGES {
                continue;
            }
            if st.mode[c] != Mode::Free && st.react[c] < pull && st.react[c] + ch[2] < pull {
                log::debug!("  switch early-lift {c}");
                self.stats.switches.early_lifts += 1;
                st.set(ct, m, c, Mode::Free, q, &mut s.held);
                s.early[c] += 1;
                switched += 1;
            } else if st.mode[c] == Mode::Stick && st.ratio[c] > 1.0 + force_tol {
                let t = s.tangential[c];
                let after = [t[0] + ch[0], t[1] + ch[1]];
                let n_after = (st.react[c] + ch[2]).max(0.0);
                let (r, _, _) = ct.stick_ratio(self.ground, c, after, n_after);
                if r > 1.0 + force_tol {
                    log::debug!("  switch early-slide {c}");
                    self.stats.switches.early_slides += 1;
                    st.set(ct, m, c, Mode::Slide, q, &mut s.held);
                    s.early[c] += 1;
                    switched += 1;
                }
            }
        }
        switched
    }

    /// Sliding contacts whose full step reverses their slip stick; free contacts that it
    /// takes below the ground land. Returns their number.
    pub(super) fn reversals_and_landings(&mut self, q: &mut [f64]) -> usize {
        let m = self.m;
        let a = m.diameter;
        let (ct, st, s, nw) = (&mut *self.ct, &mut *self.st, &mut *self.s, &mut *self.nw);
        let mut switched = 0;
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            match st.mode[c] {
                Mode::Slide => {
                    let s0 = ct.slip(c, q);
                    for kk in 0..3 {
                        nw.trial[k + kk] = q[k + kk] + nw.dq[k + kk];
                    }
                    let s1 = ct.slip(c, &nw.trial);
                    if s0[0] * s1[0] + s0[1] * s1[1] <= 0.0 {
                        log::debug!(
                            "  switch reversal {c} s0 {:.3e} {:.3e} s1 {:.3e} {:.3e}",
                            s0[0],
                            s0[1],
                            s1[0],
                            s1[1]
                        );
                        st.set(ct, m, c, Mode::Stick, q, &mut s.held);
                        self.stats.switches.reversals += 1;
                        switched += 1;
                    }
                }
                Mode::Free => {
                    if q[k + 2] + nw.dq[k + 2] < 0.5 * a {
                        let sl = ct.slip(c, q);
                        let mode = if sl[0].hypot(sl[1]) > m.solver.contact_tolerance * a {
                            Mode::Slide
                        } else {
                            Mode::Stick
                        };
                        log::debug!("  switch landing {c}");
                        self.stats.switches.landings += 1;
                        st.set(ct, m, c, mode, q, &mut s.held);
                        switched += 1;
                    }
                }
                Mode::Stick => {}
            }
        }
        switched
    }
}
