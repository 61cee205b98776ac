//! An FMI 2.0 co-simulation FMU of a scenario (docs/interop.md): the variables chosen at
//! export, the model description (FMI 2.0 standard, section 2.2 and 4.3), and the archive:
//! `modelDescription.xml`, `binaries/linux64/<id>.so` (the `fmu/` crate's library),
//! `resources/scenario.toml` with the table files it reads, `resources/foldsim-fmu.toml`
//! (the variables, read back by the library).

use crate::model::inputs::InputKind;
use crate::observe::Selection;
use crate::output::units::unit_of;
use crate::scenario::ScenarioText;
use crate::session::parameters;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The name of the variables file inside the FMU's resources.
pub const VARIABLES_FILE: &str = "foldsim-fmu.toml";
/// The name of the scenario file inside the FMU's resources.
pub const SCENARIO_FILE: &str = "scenario.toml";

/// An FMU's variables, in value-reference order: outputs, then inputs, then parameters
/// (value reference = position in that order, from 0).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variables {
    /// The FMU's GUID, checked at instantiation.
    pub guid: String,
    /// Output columns (docs/outputs.md), without `t` (the FMU's time is FMI's own).
    pub outputs: Vec<String>,
    /// Input names (crate::model::inputs).
    pub inputs: Vec<String>,
    /// Parameters: key paths and their values in the scenario.
    pub parameters: Vec<Parameter>,
}

/// One parameter of an FMU.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// Its key path (docs/scenario.md, "Key paths").
    pub path: String,
    /// The scenario's value (the FMU's start value).
    pub start: f64,
}

/// What `foldsim export fmu` is asked for.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// Output column patterns (`*`, `?`, `default`); empty: the default set.
    pub outputs: Vec<String>,
    /// Bodies (each gives its six force and torque inputs), motors, actuators, input names,
    /// or `actuators` (every actuator); empty: the hub's six.
    pub inputs: Vec<String>,
    /// Parameter key-path patterns; `None`: every number the scenario offers
    /// ([`parameters::offered`]); an empty list: none.
    pub parameters: Option<Vec<String>>,
}

/// The variables of an FMU of `text` for `request`. Errors name the pattern or name that is
/// wrong and say what would be valid.
pub fn variables(text: &ScenarioText, request: &Request) -> Result<Variables, String> {
    let mut scenario = text.build().map_err(|e| e.to_string())?;
    scenario.model.commandable = true;
    let model = &scenario.model;
    let selection = if request.outputs.is_empty() {
        Selection::default_for(model)
    } else {
        Selection::matching(model, &request.outputs).map_err(|e| format!("--outputs: {e}"))?
    };
    let outputs: Vec<String> = selection.names.into_iter().filter(|n| n != "t").collect();
    if outputs.is_empty() {
        return Err("--outputs chose only t: name at least one output column (H_*, w_B_z, deployed, ...)".into());
    }
    let every = crate::session::Inputs::of(model);
    let every = every.list();
    let hub = model.bodies[0].name.clone();
    let asked: Vec<String> = if request.inputs.is_empty() { vec![hub] } else { request.inputs.clone() };
    let mut chosen: Vec<String> = Vec::new();
    for name in &asked {
        let name = name.trim();
        let mut found: Vec<&str> = Vec::new();
        if let Some(b) = model.body_index(name) {
            found.extend(
                every
                    .iter()
                    .filter(|i| matches!(i.kind, InputKind::Force { body, .. } | InputKind::Torque { body, .. } if body == b))
                    .map(|i| i.name.as_str()),
            );
        }
        let by_prefix =
            |suffix: &str| every.iter().find(|i| i.name == format!("{name}{suffix}")).map(|i| i.name.as_str());
        found.extend(by_prefix("_effort"));
        found.extend(by_prefix("_torque"));
        found.extend(every.iter().filter(|i| i.name == name).map(|i| i.name.as_str()));
        if name == "actuators" {
            found.extend(every.iter().filter(|i| i.name.ends_with("_torque")).map(|i| i.name.as_str()));
        }
        if found.is_empty() {
            let bodies: Vec<&str> = model.bodies.iter().take(4).map(|b| b.name.as_str()).collect();
            return Err(format!(
                "--inputs {name:?} names no body, motor, actuator or input (bodies: {}{}; motors: {:?}; inputs are named like {}_T_z)",
                bodies.join(", "),
                if model.bodies.len() > 4 { ", …" } else { "" },
                model.motors.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(),
                model.bodies[0].name
            ));
        }
        for f in found {
            if !chosen.iter().any(|c| c == f) {
                chosen.push(f.to_string());
            }
        }
    }
    // In the model's order, whatever order they were asked in.
    let inputs: Vec<String> = every.iter().filter(|i| chosen.contains(&i.name)).map(|i| i.name.clone()).collect();
    let params = match &request.parameters {
        None => parameters::offered(text),
        Some(p) if p.is_empty() => Vec::new(),
        Some(p) => parameters::matching(text, p).map_err(|e| format!("--parameters: {e}"))?,
    };
    let parameters: Vec<Parameter> = params.into_iter().map(|(path, start)| Parameter { path, start }).collect();
    let names = outputs.iter().chain(&inputs).chain(parameters.iter().map(|p| &p.path));
    let mut seen = std::collections::HashSet::new();
    if let Some(dup) = names.clone().find(|n| !seen.insert(n.as_str())) {
        return Err(format!(
            "two FMU variables would both be named {dup:?}: choose fewer outputs, inputs or parameters"
        ));
    }
    let mut hash = Fnv::default();
    hash.write(text.text().as_bytes());
    for n in names {
        hash.write(n.as_bytes());
        hash.write(&[0]);
    }
    let (a, b) = (hash.0, hash.0.rotate_left(29) ^ 0x9e37_79b9_7f4a_7c15);
    let guid = format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    );
    Ok(Variables { guid, outputs, inputs, parameters })
}

/// FNV-1a, 64 bits: a GUID that is the same for the same scenario and variables on every
/// machine and Rust version (std's hasher promises neither).
#[derive(Clone, Copy)]
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// A C identifier made of `stem` (an FMU's `modelIdentifier`, the name of its library).
pub fn model_identifier(stem: &str) -> String {
    let mut id: String = stem.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert(0, 'm');
    }
    id
}

/// The FMI 2.0 model description of an FMU with `variables`, of a scenario titled `title`,
/// whose run lasts `duration` s with rows every `output_step` s (the default experiment).
pub fn model_description(
    variables: &Variables,
    identifier: &str,
    title: &str,
    duration: f64,
    output_step: f64,
) -> String {
    let mut units: Vec<&str> = Vec::new();
    let mut body = String::new();
    let mut index = 0;
    let mut outputs_xml = String::new();
    let mut add = |name: &str, attrs: &str, real: String, description: String, body: &mut String| {
        index += 1;
        body.push_str(&format!(
            "    <ScalarVariable name=\"{}\" valueReference=\"{}\" description=\"{}\" {attrs}>\n      <Real{real}/>\n    </ScalarVariable>\n",
            xml(name),
            index - 1,
            xml(&description)
        ));
        index
    };
    let unit_attr = |u: &'static str, units: &mut Vec<&'static str>| -> String {
        let u = fmi_unit(u);
        if u.is_empty() {
            return String::new();
        }
        if !units.contains(&u) {
            units.push(u);
        }
        format!(" unit=\"{}\"", xml(u))
    };
    for name in &variables.outputs {
        let real = unit_attr(unit_of(name), &mut units);
        let i = add(
            name,
            "causality=\"output\" variability=\"continuous\" initial=\"calculated\"",
            real,
            format!("output column {name} (docs/outputs.md)"),
            &mut body,
        );
        outputs_xml.push_str(&format!("      <Unknown index=\"{i}\"/>\n"));
    }
    for name in &variables.inputs {
        let u = input_unit(name);
        let real = format!("{} start=\"0.0\"", unit_attr(u, &mut units));
        let what = if name.ends_with("_effort") {
            "motor effort, replaces its drive once the FMU starts"
        } else if name.ends_with("_torque") {
            "actuator torque; the FMU's inputs replace the control law"
        } else {
            "in the body's own frame, at its centre of mass"
        };
        add(name, "causality=\"input\" variability=\"continuous\"", real, format!("{name}: {what}"), &mut body);
    }
    for p in &variables.parameters {
        let real = format!(" start=\"{}\"", fmt(p.start));
        add(
            &p.path,
            "causality=\"parameter\" variability=\"fixed\" initial=\"exact\"",
            real,
            format!("scenario value {} (key path)", p.path),
            &mut body,
        );
    }
    let unit_defs: String = units.iter().map(|u| format!("    <Unit name=\"{}\"/>\n", xml(u))).collect();
    let unit_block = if units.is_empty() {
        String::new()
    } else {
        format!("  <UnitDefinitions>\n{unit_defs}  </UnitDefinitions>\n")
    };
    let structure = if outputs_xml.is_empty() {
        String::new()
    } else {
        format!(
            "    <Outputs>\n{outputs_xml}    </Outputs>\n    <InitialUnknowns>\n{outputs_xml}    </InitialUnknowns>\n"
        )
    };
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="{name}" guid="{guid}" description="{desc}" generationTool="foldsim {version}" variableNamingConvention="flat" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{identifier}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false" canSerializeFMUstate="false" providesDirectionalDerivative="false"/>
{unit_block}  <DefaultExperiment startTime="0.0" stopTime="{stop}" stepSize="{step}"/>
  <ModelVariables>
{body}  </ModelVariables>
  <ModelStructure>
{structure}  </ModelStructure>
</fmiModelDescription>
"#,
        name = xml(identifier),
        guid = variables.guid,
        desc = xml(&format!("foldsim: {title}")),
        version = env!("CARGO_PKG_VERSION"),
        stop = fmt(duration),
        step = fmt(output_step),
    )
}

/// An input's unit, by its name.
fn input_unit(name: &str) -> &'static str {
    if name.ends_with("_effort") {
        ""
    } else if ["_F_x", "_F_y", "_F_z"].iter().any(|s| name.ends_with(s)) {
        "N"
    } else {
        "N·m"
    }
}

/// A unit as FMI spells it (ASCII: `N.m`, `kg.m2/s`); empty where the quantity has none.
fn fmi_unit(u: &str) -> &'static str {
    match u {
        "s" => "s",
        "rad" => "rad",
        "N" => "N",
        "N·m" => "N.m",
        "m/s" => "m/s",
        "rad/s" => "rad/s",
        "m" => "m",
        "kg·m/s" => "kg.m/s",
        "kg·m²/s" => "kg.m2/s",
        "J" => "J",
        "kg·m²" => "kg.m2",
        "N·m·s" => "N.m.s",
        _ => "",
    }
}

/// A number as the shortest text that reads back to it.
fn fmt(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'E']) || s.contains("inf") || s.contains("NaN") { s } else { format!("{s}.0") }
}

/// Text escaped for an XML attribute.
fn xml(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&apos;")
}

/// The FMU archive's bytes: the description, `library` (the `fmu/` crate's shared library)
/// as `binaries/linux64/<identifier>.so`, the scenario text and the files it reads (each
/// under `resources/` at its path relative to `base`, the scenario's directory), the
/// variables file.
pub fn archive(
    description: &str,
    identifier: &str,
    library: &[u8],
    scenario_text: &str,
    tables: &[(PathBuf, Vec<u8>)],
    variables: &Variables,
) -> Result<Vec<u8>, String> {
    use std::io::Write;
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    let vars = toml::to_string(variables).map_err(|e| format!("the FMU's variables as TOML: {e}"))?;
    let mut files: Vec<(String, &[u8])> = vec![
        ("modelDescription.xml".into(), description.as_bytes()),
        (format!("binaries/linux64/{identifier}.so"), library),
        (format!("resources/{SCENARIO_FILE}"), scenario_text.as_bytes()),
        (format!("resources/{VARIABLES_FILE}"), vars.as_bytes()),
    ];
    for (rel, bytes) in tables {
        files.push((format!("resources/{}", rel.to_string_lossy().replace('\\', "/")), bytes));
    }
    for (name, bytes) in files {
        zip.start_file(name.clone(), options).map_err(|e| format!("the FMU archive, {name}: {e}"))?;
        zip.write_all(bytes).map_err(|e| format!("the FMU archive, {name}: {e}"))?;
    }
    let cursor = zip.finish().map_err(|e| format!("the FMU archive: {e}"))?;
    Ok(cursor.into_inner())
}

/// The files a scenario read besides itself (`inputs`, the scenario's first), each with its
/// path relative to `base` (the scenario's directory) and its bytes. A file outside `base`
/// cannot be placed in the FMU's resources beside the scenario: refused, naming it.
pub fn table_files(inputs: &[PathBuf], base: &Path) -> Result<Vec<(PathBuf, Vec<u8>)>, String> {
    let base_c = std::fs::canonicalize(if base.as_os_str().is_empty() { Path::new(".") } else { base })
        .map_err(|e| format!("{}: {e}", base.display()))?;
    let mut out = Vec::new();
    for p in inputs.iter().skip(1) {
        let c = std::fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let rel = c.strip_prefix(&base_c).map_err(|_| {
            format!(
                "{} is read by the scenario but lies outside its directory {}: an FMU carries the scenario's files beside it; move the table under the scenario's directory",
                p.display(),
                base_c.display()
            )
        })?;
        if out.iter().any(|(r, _)| r == rel) {
            continue; // read by several hinges: packed once
        }
        let bytes = std::fs::read(&c).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
        out.push((rel.to_path_buf(), bytes));
    }
    Ok(out)
}
