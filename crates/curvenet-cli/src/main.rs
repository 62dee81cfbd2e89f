//! The `curvenet` command-line tool.
fn main() {
    eprintln!("curvenet: command-line interface under construction");
    std::process::exit(2);
}
