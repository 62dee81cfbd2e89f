//! The OpenSeesPy script of a structural model ([`super::structural::StructuralModel`]): the
//! model as JSON in the script, and a generic builder and analysis (`opensees.py`, kept as a
//! Python file so it reads and lints as one) that, run as it is, prints the model's lowest
//! natural frequencies and its linear self-weight deflection as one JSON line,
//! `{"units", "frequencies_hz", "self_weight_max_deflection"}`, in the model's units.
//!
//! Written by hand: no crate writes OpenSees models; the format is OpenSeesPy's commands
//! (`node`, `fix`, `equalDOF`, `geomTransf`, `elasticBeamColumn`, `zeroLength`, `mass`,
//! `eigen`, a linear static analysis).

use super::structural::StructuralModel;

/// The generic part of the script.
const BODY: &str = include_str!("opensees.py");

/// The script of `model`.
pub fn opensees_script(model: &StructuralModel) -> String {
    let mut out = String::from("#!/usr/bin/env python3\n");
    out.push_str(&format!(
        "# curvenet: an OpenSeesPy model of {}\n",
        model.source.replace('\n', " ")
    ));
    if let Some(why) = &model.unstable {
        out.push_str(&format!("# {}\n", super::unstable_header(why)));
    }
    out.push_str(BODY);
    // The model last, so the body reads first; `main` runs after it is defined. JSON escapes
    // every quote, so the raw string cannot end early.
    let at = out
        .rfind("\n\nif __name__ == \"__main__\":")
        .unwrap_or(out.len());
    let json = serde_json::to_string(model).unwrap_or_else(|_| "null".into());
    out.insert_str(at, &format!("\n\nMODEL = json.loads(r\"\"\"{json}\"\"\")"));
    out
}
