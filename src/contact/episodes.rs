//! The contact event log (docs/contact.md, *Episodes*): every episode of every body pair,
//! from the accepted state where the pair first has a point in contact to the first accepted
//! state where it has none, with its deepest penetration, peak force and the normal speed at
//! which its points came into contact; the stowed package resting on itself told apart from
//! the impacts after the start (or after a launch restraint lets go).

use super::ContactPoint;
use std::collections::BTreeMap;

/// One episode of contact between two bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Episode {
    /// The two bodies, lower index first.
    pub bodies: (usize, usize),
    /// First accepted state in contact, s.
    pub start: f64,
    /// First accepted state out of contact again, s (`None`: still in contact at the end).
    pub end: Option<f64>,
    /// Deepest penetration of any of its points, m, and when, s.
    pub deepest: (f64, f64),
    /// Largest total force between the two bodies, N, and when, s.
    pub peak_force: (f64, f64),
    /// The largest normal speed at which one of its points came into contact, m/s (the
    /// approach speed at the first accepted state it was in contact).
    pub impact_speed: f64,
    /// In contact from the start of the run (or before the launch restraint let go): the
    /// stowed package resting on itself, not an impact.
    pub resting: bool,
    /// A hinge joins the two bodies: neighbours whose edges meet as their crease closes or
    /// rings, as expected of them (false: bodies no hinge joins, a strike of the structure on
    /// itself). The contact code knows nothing of hinges: the log leaves it false and the
    /// dynamics sets it from the model's hinges when it hands the episodes on.
    pub joined: bool,
}

/// The episodes of a run so far.
#[derive(Clone, Debug, Default)]
pub struct ContactLog {
    /// Up to this time (s) an episode that starts is resting contact: 0, or the release of
    /// the launch restraint.
    pub resting_until: f64,
    open: BTreeMap<(usize, usize), Episode>,
    closed: Vec<Episode>,
}

impl ContactLog {
    /// Takes in the accepted state at time `t` (s) with contact points `points`; `entry`
    /// gives a point that was not in contact at the last accepted state its impact speed
    /// (m/s; `None` for one that was).
    pub fn record(&mut self, t: f64, points: &[ContactPoint], entry: impl Fn(&ContactPoint) -> Option<f64>) {
        let mut now: BTreeMap<(usize, usize), (f64, nalgebra::Vector3<f64>, f64)> = BTreeMap::new();
        for p in points {
            let (a, b) = (p.key.body.min(p.key.other) as usize, p.key.body.max(p.key.other) as usize);
            let sign = if p.key.body as usize == a { 1.0 } else { -1.0 };
            let e = now.entry((a, b)).or_insert((0.0, nalgebra::Vector3::zeros(), 0.0));
            e.0 = e.0.max(p.depth);
            e.1 += p.force_in_n * sign;
            if let Some(speed) = entry(p) {
                e.2 = e.2.max(speed);
            }
        }
        let ended: Vec<(usize, usize)> = self.open.keys().filter(|k| !now.contains_key(k)).copied().collect();
        for k in ended {
            let mut e = self.open.remove(&k).expect("open");
            e.end = Some(t);
            self.closed.push(e);
        }
        for (pair, (depth, force, speed)) in now {
            let force = force.norm();
            let e = self.open.entry(pair).or_insert(Episode {
                bodies: pair,
                start: t,
                end: None,
                deepest: (0.0, t),
                peak_force: (0.0, t),
                impact_speed: 0.0,
                resting: t <= self.resting_until,
                joined: false,
            });
            if depth > e.deepest.0 {
                e.deepest = (depth, t);
            }
            if force > e.peak_force.0 {
                e.peak_force = (force, t);
            }
            e.impact_speed = e.impact_speed.max(speed);
        }
    }

    /// Whether `p`'s pair is in a resting episode now (the stowed package on itself).
    pub fn is_resting(&self, p: &ContactPoint) -> bool {
        let pair = (p.key.body.min(p.key.other) as usize, p.key.body.max(p.key.other) as usize);
        self.open.get(&pair).is_some_and(|e| e.resting)
    }

    /// Every episode so far, in the order they started (those still open with no end).
    pub fn episodes(&self) -> Vec<Episode> {
        let mut all: Vec<Episode> = self.closed.iter().chain(self.open.values()).copied().collect();
        all.sort_by(|x, y| x.start.total_cmp(&y.start).then(x.bodies.cmp(&y.bodies)));
        all
    }
}

/// The episodes as CSV, one row each: the bodies' names, when, how deep, how hard, how fast,
/// whether it is the stowed package's resting contact or an impact, and whether a hinge
/// joins the two bodies.
pub fn episodes_csv(episodes: &[Episode], names: &[&str]) -> String {
    let mut out = String::from(
        "body_a,body_b,kind,start_s,end_s,impact_speed_m_s,deepest_m,deepest_at_s,peak_force_n,peak_force_at_s,joined\n",
    );
    for e in episodes {
        let end = e.end.map_or(String::new(), |t| t.to_string());
        out.push_str(&format!(
            "{},{},{},{},{end},{},{},{},{},{},{}\n",
            names[e.bodies.0],
            names[e.bodies.1],
            if e.resting { "resting" } else { "impact" },
            e.start,
            e.impact_speed,
            e.deepest.0,
            e.deepest.1,
            e.peak_force.0,
            e.peak_force.1,
            e.joined
        ));
    }
    out
}
