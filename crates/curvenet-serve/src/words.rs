//! The server's words for the library's messages: options named by the JSON fields a request
//! sets (`max_gap`, `min_curves`, …), and the surface by how the server is given it.

use curvenet::words::{Message, Opt, Wording};

/// Options as the API spells them: the request's JSON field (`max_gap`, `max_gap 900`); the
/// mesh is given when the server starts, so it reads `serve with --mesh`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Fields;

impl Wording for Fields {
    fn option(&self, opt: Opt) -> String {
        match opt {
            Opt::Mesh => "serve with --mesh".to_string(),
            o => o.key().to_string(),
        }
    }
}

/// A message in the API's words.
pub fn say(m: &Message) -> String {
    m.render(&Fields)
}

#[cfg(test)]
mod tests {
    use super::*;
    use curvenet::words::message;

    #[test]
    fn options_read_as_the_fields_of_a_request() {
        let m = message![
            Opt::MaxGap,
            " measures the gap over the surface: give the mesh (",
            Opt::Mesh,
            ")"
        ];
        assert_eq!(
            say(&m),
            "max_gap measures the gap over the surface: give the mesh (serve with --mesh)"
        );
    }
}
