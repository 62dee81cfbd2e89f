//! The page at `/`: the viewer in its app mode ([`curvenet::report::viewer::app_html`]) over
//! the workspace's network, surface and current structure; its script edits the structure
//! through the JSON API. Self-contained: it loads nothing but this server's API.

use crate::api::Gravity;
use crate::workspace::Workspace;
use curvenet::run_folder::instability;
use serde_json::{Value, json};

/// The page of `ws`, titled after what is served (an example, files, a run).
///
/// # Errors
///
/// The page's data cannot be written (it always can).
pub fn page(ws: &Workspace) -> Result<String, String> {
    let analyzer = ws.design.analyzer();
    let net = analyzer.network();
    let params = analyzer.params();
    let physical = analyzer.physical().map(|p| {
        json!({
            "units": p.physical.units.to_string(),
            "material": p.physical.material.name,
        })
    });
    let setup = json!({
        "example": &*ws.name,
        "supports": net.supports.name(),
        "material": params.material,
        "gravity": params.gravity,
        "budget": null,
        "total_length": ws.design.total_length(),
        "complete": true,
        "stop": null,
        "physical": physical,
        // The physical mode's scene unit: the lengths shown carry it.
        "units": analyzer.physical().map(|p| p.physical.units.symbol()),
    });
    let objective = params.objective;
    let objective = json!({
        "name": objective.name(),
        "value": objective.value_symbol(),
        "score": objective.score_symbol(),
    });
    let title = format!("curvenet serve: {}", ws.name);
    let before = ws.slid.as_ref().map(|s| s.before.as_slice());
    curvenet::report::viewer::app_html(
        net,
        &title,
        setup,
        live(ws),
        ws.mesh.as_deref(),
        objective,
        before,
    )
    .map_err(|e| e.to_string())
}

/// The current structure as the viewer's live structure: the summary's numbers (an unstable
/// structure named as such), the equilibrium displacements, the worst-case mode and the
/// gravity deflection in full.
pub fn live(ws: &Workspace) -> Value {
    let c = ws.design.current();
    let mut v = serde_json::to_value(&c.summary).unwrap_or_else(|_| json!({}));
    let s = &c.summary;
    v["unstable"] = json!(instability(s.lambda, s.zero_modes, s.negative_modes));
    v["removed"] = Value::Null;
    v["score"] = Value::Null;
    v["u"] = json!({ "full": c.displacement });
    v["mode"] = json!({ "full": c.mode });
    v["gravity"] = match Gravity::of(ws, &c) {
        Some(g) => json!({
            "full": g.displacement,
            "max_displacement": g.max_displacement,
            "vertex": g.vertex,
        }),
        None => Value::Null,
    };
    v
}
