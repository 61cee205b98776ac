//! The scenario file's structure as serde reads it, before any check: every key of
//! `docs/scenario.md`, with its position in the file kept for errors.

use super::values::Exact;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScenario {
    pub(super) title: Option<String>,
    pub(super) run: Spanned<RawRun>,
    #[serde(rename = "body", default)]
    pub(super) bodies: Vec<RawBody>,
    #[serde(rename = "hinge", default)]
    pub(super) hinges: Vec<RawHinge>,
    #[serde(default)]
    pub(super) initial: RawInitial,
    pub(super) contact: Option<Spanned<RawContact>>,
    #[serde(rename = "load", default)]
    pub(super) loads: Vec<super::loads::RawLoad>,
    #[serde(rename = "motor", default)]
    pub(super) motors: Vec<super::actuators::RawMotor>,
    pub(super) control: Option<Spanned<super::actuators::RawControl>>,
    /// A sweep's distributions and metrics (read by `crate::sweep`; a run ignores it and
    /// runs the nominal values).
    #[allow(dead_code)]
    pub(super) sweep: Option<toml::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRun {
    pub(super) duration: Spanned<f64>,
    pub(super) output_step: Spanned<f64>,
    pub(super) integrator: Option<Spanned<String>>,
    pub(super) error_norm: Option<Spanned<String>>,
    pub(super) rtol: Option<Spanned<f64>>,
    pub(super) atol: Option<Spanned<f64>>,
    pub(super) position_tolerance: Option<Spanned<f64>>,
    pub(super) step: Option<Spanned<f64>>,
    pub(super) rho_inf: Option<Spanned<f64>>,
    pub(super) max_steps: Option<Spanned<i64>>,
    pub(super) release_at: Option<Spanned<f64>>,
    pub(super) columns: Option<Spanned<Vec<String>>>,
    pub(super) csv: Option<String>,
}

/// `[contact]`: the contact law and which pairs take part (docs/contact.md).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawContact {
    pub(super) stiffness: Spanned<f64>,
    pub(super) exponent: Option<Spanned<f64>>,
    pub(super) restitution: Spanned<f64>,
    pub(super) friction: Option<Spanned<f64>>,
    pub(super) slip_speed: Option<Spanned<f64>>,
    pub(super) min_impact_speed: Option<Spanned<f64>>,
    pub(super) margin: Option<Spanned<f64>>,
    pub(super) spacing: Option<Spanned<f64>>,
    pub(super) exclude: Option<Spanned<Vec<Exact<Spanned<String>, 2>>>>,
    pub(super) allow_initial_overlap: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBody {
    pub(super) name: Spanned<String>,
    pub(super) mass: Option<Spanned<f64>>,
    pub(super) inertia: Option<Spanned<toml::Value>>,
    pub(super) shape: Option<Spanned<RawShape>>,
    pub(super) density: Option<Spanned<f64>>,
}

/// `shape = { polygon = [[x, y, z], …], thickness = … }` or `shape = { box = [a, b, c] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawShape {
    pub(super) polygon: Option<Vec<Exact<f64, 3>>>,
    pub(super) thickness: Option<f64>,
    #[serde(rename = "box")]
    pub(super) cuboid: Option<Exact<f64, 3>>,
    pub(super) cylinder: Option<RawCylinder>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCylinder {
    pub(super) radius: f64,
    pub(super) height: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHinge {
    pub(super) name: Spanned<String>,
    pub(super) parent: Spanned<String>,
    pub(super) child: Spanned<String>,
    pub(super) a0: Spanned<toml::Value>,
    pub(super) a: Spanned<RawChildFrame>,
    pub(super) law: Spanned<RawLaw>,
}

/// Angle keys shared by every table that holds an orientation.
#[derive(Deserialize, Default, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFrame {
    pub(super) position: Option<Exact<f64, 3>>,
    pub(super) yaw: Option<f64>,
    pub(super) yaw_deg: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) pitch_deg: Option<f64>,
    pub(super) roll: Option<f64>,
    pub(super) roll_deg: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawChildFrame {
    pub(super) child_com: Exact<f64, 3>,
    pub(super) yaw: Option<f64>,
    pub(super) yaw_deg: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) pitch_deg: Option<f64>,
    pub(super) roll: Option<f64>,
    pub(super) roll_deg: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLaw {
    #[serde(rename = "type")]
    pub(super) kind: Spanned<String>,
    pub(super) k_f: Option<Spanned<toml::Value>>,
    pub(super) k_theta: Option<Spanned<toml::Value>>,
    pub(super) c_f: Option<Spanned<toml::Value>>,
    pub(super) c_theta: Option<Spanned<toml::Value>>,
    pub(super) angles: Option<Spanned<String>>,
    pub(super) x: Option<Spanned<DirectionEntry>>,
    pub(super) y: Option<Spanned<DirectionEntry>>,
    pub(super) z: Option<Spanned<DirectionEntry>>,
    pub(super) rx: Option<Spanned<DirectionEntry>>,
    pub(super) ry: Option<Spanned<DirectionEntry>>,
    pub(super) rz: Option<Spanned<DirectionEntry>>,
}

/// One direction of a directional law: a table of keys, or the shorthand word `"free"` or
/// `"locked"`.
pub(super) struct DirectionEntry(pub(super) RawDirection);

impl<'de> Deserialize<'de> for DirectionEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Entry;
        impl<'de> serde::de::Visitor<'de> for Entry {
            type Value = DirectionEntry;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "\"free\", \"locked\" or a table of response keys such as { k = 100.0 } (docs/hinge-laws.md)",
                )
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<DirectionEntry, E> {
                match v {
                    "free" => Ok(DirectionEntry(RawDirection { free: Some(true), ..Default::default() })),
                    "locked" => Ok(DirectionEntry(RawDirection { locked: Some(true), ..Default::default() })),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<DirectionEntry, A::Error> {
                RawDirection::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(DirectionEntry)
            }
        }
        d.deserialize_any(Entry)
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDirection {
    pub(super) free: Option<bool>,
    pub(super) locked: Option<bool>,
    pub(super) k: Option<f64>,
    pub(super) table: Option<Spanned<RawTable>>,
    pub(super) table2d: Option<Spanned<RawTable2>>,
    pub(super) tape_spring: Option<Spanned<RawTapeSpring>>,
    pub(super) rest: Option<f64>,
    pub(super) rest_deg: Option<f64>,
    pub(super) damping: Option<f64>,
    pub(super) stop: Option<Spanned<RawStop>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTable {
    pub(super) file: Option<String>,
    pub(super) points: Option<Vec<Exact<f64, 2>>>,
    /// Multiplies the table's values (forces, moments): a measured curve's shape with its
    /// magnitude set or fitted (docs/fit.md).
    pub(super) scale: Option<Spanned<f64>>,
    pub(super) interpolation: Spanned<String>,
    pub(super) outside: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTable2 {
    pub(super) file: String,
    pub(super) other: Spanned<String>,
    pub(super) interpolation: Spanned<String>,
    pub(super) outside: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTapeSpring {
    pub(super) increasing: Spanned<RawTable>,
    pub(super) decreasing: Spanned<RawTable>,
    pub(super) transition_stiffness: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStop {
    pub(super) at: Option<f64>,
    pub(super) at_deg: Option<f64>,
    pub(super) free: Spanned<String>,
    pub(super) band: Option<Spanned<f64>>,
    pub(super) band_deg: Option<Spanned<f64>>,
    pub(super) stiffness: Spanned<f64>,
    pub(super) damping: Spanned<f64>,
    #[serde(default)]
    pub(super) lock: bool,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawInitial {
    pub(super) hub: Option<Spanned<RawHubInitial>>,
    #[serde(default)]
    pub(super) hinge: BTreeMap<Spanned<String>, Spanned<RawHingeInitial>>,
    #[serde(default)]
    pub(super) body: BTreeMap<Spanned<String>, Spanned<RawAngles>>,
    #[serde(rename = "loop", default)]
    pub(super) loop_hinge: BTreeMap<Spanned<String>, Spanned<RawAngles>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHubInitial {
    pub(super) position: Option<Exact<f64, 3>>,
    pub(super) velocity: Option<Exact<f64, 3>>,
    pub(super) omega: Option<Exact<f64, 3>>,
    pub(super) omega_deg_s: Option<Exact<f64, 3>>,
    pub(super) omega_rpm: Option<Exact<f64, 3>>,
    pub(super) yaw: Option<f64>,
    pub(super) yaw_deg: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) pitch_deg: Option<f64>,
    pub(super) roll: Option<f64>,
    pub(super) roll_deg: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHingeInitial {
    pub(super) delta: Option<Exact<f64, 3>>,
    pub(super) delta_rate: Option<Exact<f64, 3>>,
    pub(super) omega_rel: Option<Exact<f64, 3>>,
    pub(super) omega_rel_deg_s: Option<Exact<f64, 3>>,
    pub(super) omega_rel_rpm: Option<Exact<f64, 3>>,
    pub(super) yaw: Option<f64>,
    pub(super) yaw_deg: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) pitch_deg: Option<f64>,
    pub(super) roll: Option<f64>,
    pub(super) roll_deg: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAngles {
    pub(super) yaw: Option<f64>,
    pub(super) yaw_deg: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) pitch_deg: Option<f64>,
    pub(super) roll: Option<f64>,
    pub(super) roll_deg: Option<f64>,
}
