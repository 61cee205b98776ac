//! The located hinge events of a run as a CSV table (`foldsim run --events`): one row per
//! stop hit, stop left and latch, in time order (docs/outputs.md, *Hinge events*).

use crate::dynamics::LawEvent;
use crate::law::EventKind;

/// The table's header.
pub const HEADER: &str = "t_s,hinge,kind,description,hinge_dissipated_j";

/// A word per kind of event, as the table writes it.
pub fn kind_word(kind: EventKind) -> &'static str {
    match kind {
        EventKind::Contact => "stop_hit",
        EventKind::Separation => "stop_left",
        EventKind::Latch => "latch",
        EventKind::Branch => "branch",
    }
}

/// `events` as CSV: time (s), the hinge's name from `hinge_names` (model order), the kind,
/// the law's description (quoted, RFC 4180) and the energy the hinge had dissipated up to
/// the event (J).
pub fn events_csv(events: &[LawEvent], hinge_names: &[&str]) -> String {
    let mut out = format!("{HEADER}\n");
    for e in events {
        out.push_str(&format!(
            "{},{},{},{},{}\n",
            e.t,
            quoted(hinge_names[e.hinge]),
            kind_word(e.kind),
            quoted(&e.description),
            e.hinge_dissipated
        ));
    }
    out
}

/// `s` in double quotes, its own quotes doubled (RFC 4180).
fn quoted(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\""))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row per event, names and descriptions quoted (a comma or quote in them survives).
    #[test]
    fn rows_in_order_with_quoted_text() {
        let e = |t: f64, hinge: usize, kind: EventKind, d: &str| LawEvent {
            t,
            hinge,
            kind,
            description: d.into(),
            hinge_dissipated: 0.5 * t,
        };
        let events = [
            e(0.25, 1, EventKind::Contact, "rz: hits the stop at 0.000000"),
            e(0.5, 0, EventKind::Latch, "a \"latch\", at 1"),
        ];
        let table = events_csv(&events, &["h,0", "h1"]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines[0], HEADER);
        assert_eq!(lines[1], "0.25,\"h1\",stop_hit,\"rz: hits the stop at 0.000000\",0.125");
        assert_eq!(lines[2], "0.5,\"h,0\",latch,\"a \"\"latch\"\", at 1\",0.25");
        assert_eq!(lines.len(), 3);
    }
}
