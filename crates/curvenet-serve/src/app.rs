//! The page at `/`: the viewer in its app mode ([`curvenet::report::viewer::app_html`]) over
//! the design's network and current structure; its script edits the structure through the
//! JSON API. Self-contained: it loads nothing but this server's API.

use crate::design::Design;
use curvenet::run_folder::instability;
use serde_json::{Value, json};

/// The page of `design`, titled after `name` (what is served: an example, files, a run).
///
/// # Errors
///
/// The page's data cannot be written (it always can).
pub fn page(design: &Design, name: &str) -> Result<String, String> {
    let analyzer = design.analyzer();
    let net = analyzer.network();
    let params = analyzer.params();
    let all: Vec<usize> = (0..net.rods.len()).collect();
    let setup = json!({
        "example": name,
        "supports": net.supports.name(),
        "material": params.material,
        "gravity": params.gravity,
        "budget": null,
        "total_length": analyzer.total_length(&all),
        "complete": true,
        "stop": null,
    });
    let title = format!("curvenet serve: {name}");
    curvenet::report::viewer::app_html(net, &title, setup, live(design))
}

/// The current structure as the viewer's live structure: the summary's numbers (an unstable
/// structure named as such), the equilibrium displacements and the worst-case mode in full.
pub fn live(design: &Design) -> Value {
    let c = design.current();
    let mut v = serde_json::to_value(&c.summary).unwrap_or_else(|_| json!({}));
    let s = &c.summary;
    v["unstable"] = json!(instability(s.lambda, s.zero_modes, s.negative_modes));
    v["removed"] = Value::Null;
    v["score"] = Value::Null;
    v["u"] = json!({ "full": c.displacement });
    v["mode"] = json!({ "full": c.mode });
    v
}
