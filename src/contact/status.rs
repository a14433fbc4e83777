//! A contact's status at an iterate of the semi-smooth Newton (free, sticking, sliding): the
//! branch of its Alart-Curnier function, and the coordinates that branch holds.

/// Status of a contact at an iterate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactStatus {
    /// Off the ground, no force.
    Free,
    /// On the ground, no slip.
    Stick,
    /// On the ground, sliding.
    Slide,
}

impl ContactStatus {
    /// The contact node's coordinates (0, 1, 2: `x, y, z`) held by this status: none when
    /// free, all three when sticking, the height when sliding.
    pub fn held(self) -> std::ops::Range<usize> {
        match self {
            ContactStatus::Free => 0..0,
            ContactStatus::Stick => 0..3,
            ContactStatus::Slide => 2..3,
        }
    }
}
