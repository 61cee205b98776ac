//! Hinge-law events seen from the whole structure: every hinge's event functions in one
//! vector, evaluated at a state, and applied when the simulator has located one.

use super::{Dynamics, LawEvent};

impl Dynamics<'_> {
    /// The hinge whose law owns event function `index`, and the index among its own.
    fn event_owner(&self, index: usize) -> (usize, usize) {
        let i = self.event_offsets.partition_point(|&o| o <= index) - 1;
        (i, index - self.event_offsets[i])
    }

    /// Total number of event functions over all hinges.
    pub fn event_count(&self) -> usize {
        *self.event_offsets.last().unwrap_or(&0)
    }

    /// Every hinge's event function values at `y` (see
    /// [`crate::law::HingeLaw::event_values`]), concatenated.
    pub fn event_values(&self, y: &[f64], out: &mut [f64]) {
        if self.event_count() == 0 {
            return;
        }
        let (mem, refs) = (self.memories.borrow(), self.theta_refs.borrow());
        for (i, h) in self.model.hinges.iter().enumerate() {
            let (a, b) = (self.event_offsets[i], self.event_offsets[i + 1]);
            // Only hinges whose laws have events: the others' kinematics are not needed.
            if b > a {
                h.law.event_values(&self.kinematics_at(i, y, &refs).state, &mem[i], &mut out[a..b]);
            }
        }
    }

    /// The parent and child bodies of the hinge whose law owns event function `index`: the
    /// only bodies [`Self::event_value`] reads.
    pub fn event_bodies(&self, index: usize) -> (usize, usize) {
        let h = &self.model.hinges[self.event_owner(index).0];
        (h.parent, h.child)
    }

    /// Event function `index` alone at `y`.
    pub fn event_value(&self, index: usize, y: &[f64]) -> f64 {
        let (i, own) = self.event_owner(index);
        let h = &self.model.hinges[i];
        let k = self.kinematics_at(i, y, &self.theta_refs.borrow());
        // On the stack for the laws' usual counts (a directional law has 30): this runs at
        // every iteration of an event's root search.
        let count = h.law.event_count();
        let mut small = [0.0; 32];
        let mut large = Vec::new();
        let out = if count <= small.len() {
            &mut small[..count]
        } else {
            large.resize(count, 0.0);
            &mut large[..]
        };
        h.law.event_values(&k.state, &self.memories.borrow()[i], out);
        out[own]
    }

    /// Whether law event `index` only keeps a table's bookkeeping
    /// ([`crate::law::HingeLaw::bookkeeping_event`]).
    pub fn bookkeeping_event(&self, index: usize) -> bool {
        let (i, own) = self.event_owner(index);
        self.model.hinges[i].law.bookkeeping_event(own)
    }

    /// Whether law event `index` switches a slip element's mode
    /// ([`crate::law::HingeLaw::slip_event`]).
    pub fn slip_event(&self, index: usize) -> bool {
        let (i, own) = self.event_owner(index);
        self.model.hinges[i].law.slip_event(own)
    }

    /// Applies event function `index`'s change at state `y`, time `t`.
    pub fn apply_event(&self, index: usize, t: f64, y: &[f64]) -> LawEvent {
        let (i, own) = self.event_owner(index);
        let k = self.kinematics_at(i, y, &self.theta_refs.borrow());
        let (kind, description) =
            self.model.hinges[i].law.apply_event(own, &k.state, &mut self.memories.borrow_mut()[i]);
        LawEvent { t, hinge: i, kind, description, hinge_dissipated: y[self.dissipation_index(i)] }
    }
}
