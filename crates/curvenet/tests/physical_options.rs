//! The physical mode's options as written (`--units`, `--material`, `--young`, …): what they
//! resolve to, and the messages bad values get (in the command line's words).

use curvenet::material::Section;
use curvenet::physics::PhysicalOptions;
use curvenet::physics::options::check_option;
use curvenet::units::LengthUnit;
use curvenet::words::{Opt, Wording};

/// The command line's spelling of options, which the messages below are checked in.
struct Flags;

impl Wording for Flags {
    fn option(&self, opt: Opt) -> String {
        format!("--{}", opt.key().replace('_', "-"))
    }
}

fn steel_mm() -> PhysicalOptions {
    PhysicalOptions {
        units: Some("mm".into()),
        material: Some("steel".into()),
        radius: Some("10".into()),
        ..Default::default()
    }
}

#[test]
fn paper_mode_without_units_or_material() {
    assert_eq!(PhysicalOptions::default().resolve(None, &[]), Ok(None));
    let stray = PhysicalOptions {
        density: Some("7850kg/m3".into()),
        ..Default::default()
    };
    let e = stray.resolve(None, &[]).unwrap_err().render(&Flags);
    assert!(e.contains("--density") && e.contains("--units"), "{e}");
}

#[test]
fn steel_in_millimetres() {
    let p = steel_mm().resolve(None, &[]).unwrap().unwrap();
    assert_eq!(p.physical.units, LengthUnit::Millimetre);
    assert_eq!(p.physical.material.young_pa, 210e9);
    assert_eq!(p.physical.section, Section::Solid { radius: 10.0 });
    assert_eq!(p.physical.load_n_per_m, 1000.0);
    assert_eq!(p.physical.gravity, [0.0, 0.0, -9.81]);
    let o = PhysicalOptions {
        young: Some("200 GPa".into()),
        radius: None,
        tube: Some("60x4".into()),
        load: Some("2kN/m".into()),
        gravity: Some("0,-9.81,0".into()),
        ..steel_mm()
    };
    let p = o.resolve(None, &[]).unwrap().unwrap();
    assert_eq!(p.physical.material.young_pa, 200e9);
    assert_eq!(p.physical.material.name, "steel (modified)");
    assert_eq!(
        p.physical.section,
        Section::Tube {
            outer_diameter: 60.0,
            wall: 4.0
        }
    );
    assert_eq!(p.physical.load_n_per_m, 2000.0);
    assert_eq!(p.physical.gravity, [0.0, -9.81, 0.0]);
    // A radius with a unit in a metre scene.
    let o = PhysicalOptions {
        units: Some("m".into()),
        radius: Some("10mm".into()),
        ..steel_mm()
    };
    let p = o.resolve(None, &[]).unwrap().unwrap();
    assert_eq!(p.physical.section, Section::Solid { radius: 0.01 });
}

#[test]
fn bad_values_name_their_option() {
    let cases: [(PhysicalOptions, &[&str]); 10] = [
        (
            PhysicalOptions {
                material: Some("unobtainium".into()),
                ..steel_mm()
            },
            &["--material", "unobtainium", "steel"],
        ),
        (
            PhysicalOptions {
                units: Some("furlong".into()),
                ..steel_mm()
            },
            &["--units", "furlong"],
        ),
        (
            PhysicalOptions {
                density: Some("-7850kg/m3".into()),
                ..steel_mm()
            },
            &["--density", "positive"],
        ),
        (
            PhysicalOptions {
                young: Some("210kg/m3".into()),
                ..steel_mm()
            },
            &["--young", "density"],
        ),
        (
            PhysicalOptions {
                strength: Some("355".into()),
                ..steel_mm()
            },
            &["--strength", "needs a unit"],
        ),
        (
            PhysicalOptions {
                tube: Some("60".into()),
                ..steel_mm()
            },
            &["--radius", "--tube"],
        ),
        (
            PhysicalOptions {
                radius: None,
                tube: Some("60x40".into()),
                ..steel_mm()
            },
            &["--tube"],
        ),
        (
            PhysicalOptions {
                radius: Some("-1".into()),
                ..steel_mm()
            },
            &["--radius"],
        ),
        (
            PhysicalOptions {
                load: Some("1kN".into()),
                ..steel_mm()
            },
            &["--load"],
        ),
        (
            PhysicalOptions {
                units: None,
                ..steel_mm()
            },
            &["--units"],
        ),
    ];
    for (o, words) in cases {
        let e = o.resolve(None, &[]).unwrap_err().render(&Flags);
        for w in words {
            assert!(e.contains(w), "{e:?} should name {w:?}");
        }
    }
    // The curve file's units stand in for --units.
    let o = PhysicalOptions {
        units: None,
        ..steel_mm()
    };
    let p = o.resolve(Some("m"), &[]).unwrap().unwrap();
    assert_eq!(p.physical.units, LengthUnit::Metre);
    // --units alone: steel, the paper's radius 2.
    let o = PhysicalOptions {
        units: Some("mm".into()),
        ..Default::default()
    };
    let p = o.resolve(None, &[]).unwrap().unwrap();
    assert_eq!(p.physical.material.name, "steel");
    assert_eq!(p.physical.section, Section::Solid { radius: 2.0 });
}

/// Values no material has, too small as well as too large, are refused naming their option
/// (a density of 1e-300 kg/m³ made the mass metric NaN: "could not factor H − σI").
#[test]
fn absurd_quantities_are_refused_naming_their_option() {
    let cases: [(PhysicalOptions, &str); 9] = [
        (
            PhysicalOptions {
                density: Some("1e-300kg/m3".into()),
                ..steel_mm()
            },
            "--density",
        ),
        (
            PhysicalOptions {
                density: Some("1e7kg/m3".into()),
                ..steel_mm()
            },
            "--density",
        ),
        (
            PhysicalOptions {
                young: Some("1e-300GPa".into()),
                ..steel_mm()
            },
            "--young",
        ),
        (
            PhysicalOptions {
                strength: Some("1e-300Pa".into()),
                ..steel_mm()
            },
            "--strength",
        ),
        (
            PhysicalOptions {
                load: Some("1e-300N/m".into()),
                ..steel_mm()
            },
            "--load",
        ),
        (
            PhysicalOptions {
                gravity: Some("1e-300".into()),
                ..steel_mm()
            },
            "--gravity",
        ),
        (
            PhysicalOptions {
                gravity: Some("0,1e-300,0".into()),
                ..steel_mm()
            },
            "--gravity",
        ),
        (
            PhysicalOptions {
                radius: None,
                tube: Some("1e-60x1e-61".into()),
                ..steel_mm()
            },
            "--tube",
        ),
        (
            PhysicalOptions {
                radius: Some("1e-40".into()),
                ..steel_mm()
            },
            "--radius",
        ),
    ];
    for (o, option) in cases {
        let e = o.resolve(None, &[]).unwrap_err().render(&Flags);
        assert!(e.contains(option), "{o:?}: {e:?} should name {option}");
        let text = match option {
            "--density" => o.density.as_deref(),
            "--young" => o.young.as_deref(),
            "--strength" => o.strength.as_deref(),
            "--load" => o.load.as_deref(),
            "--gravity" => o.gravity.as_deref(),
            _ => None,
        };
        // Refused while the command line is parsed too (a section's stiffness needs the
        // units and the material: only resolve knows them).
        if let Some(t) = text {
            let opt = Opt::from_key(&option[2..].replace('-', "_")).expect("an option");
            assert!(check_option(opt, t).is_err(), "{option} {t}");
        }
    }
    // Gravity off stays allowed.
    let o = PhysicalOptions {
        gravity: Some("0".into()),
        ..steel_mm()
    };
    assert!(o.resolve(None, &[]).is_ok());
}

/// What a curve file says is never ignored: its `units` or a curve's own material or section
/// turn on the physical mode; without a length unit, a curve's material, section or pre-bent
/// rest shape is refused naming the curve.
#[test]
fn a_curve_files_physical_fields_turn_on_the_physical_mode_or_are_refused() {
    use curvenet::material::{CurveSpec, MaterialSpec, RestShape};
    let none = PhysicalOptions::default();
    // The file's units alone: steel, the paper's radius.
    let p = none.resolve(Some("mm"), &[]).unwrap().unwrap();
    assert_eq!(p.physical.units, LengthUnit::Millimetre);
    assert_eq!(p.physical.material.name, "steel");
    let aluminium = CurveSpec {
        material: Some(MaterialSpec {
            preset: Some("aluminium".into()),
            ..Default::default()
        }),
        ..Default::default()
    };
    let specs = [CurveSpec::default(), aluminium.clone()];
    let p = none.resolve(Some("m"), &specs).unwrap().unwrap();
    assert_eq!(p.physical.units, LengthUnit::Metre);
    // A curve's own material with no unit anywhere: refused naming the curve.
    let e = none.resolve(None, &specs).unwrap_err().render(&Flags);
    assert!(e.contains("curve 1") && e.contains("--units"), "{e}");
    // A pre-bent curve in the paper's mode: refused naming the curve.
    let bent = CurveSpec {
        rest: Some(RestShape::PreBent),
        ..Default::default()
    };
    let e = none
        .resolve(
            None,
            &[CurveSpec::default(), CurveSpec::default(), bent.clone()],
        )
        .unwrap_err()
        .render(&Flags);
    assert!(e.contains("curve 2") && e.contains("pre-bent"), "{e}");
    // With the file's units it is analysed pre-bent.
    let p = none.resolve(Some("mm"), &[bent]).unwrap().unwrap();
    assert_eq!(p.rest, vec![RestShape::PreBent]);
}
