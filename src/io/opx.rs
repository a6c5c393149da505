//! ORIPA's own format, `.opx` (read only): a Java `XMLDecoder` document whose
//! `oripa.OriLineProxy` objects are the drawn lines, each with the properties `type`,
//! `x0`, `y0`, `x1`, `y1` (one left out is 0, as the decoder's default), typed as in
//! `.cp` ([`super::cp::line_type`]). The lines become a mesh as `.cp`'s do.

use super::cp::{line_type, mesh_of_lines};
use super::planar::Segment;
use super::FileCause;
use crate::mesh::{Mesh, Vec2};

/// The tag that opens one line.
const LINE: &str = "<object class=\"oripa.OriLineProxy\"";

pub fn parse(text: &str, notes: &mut Vec<String>) -> Result<Mesh, FileCause> {
    if !text.contains("java.beans.XMLDecoder") && !text.contains("oripa.") {
        return Err(
            "not an ORIPA .opx document (no java.beans.XMLDecoder of oripa objects)".into(),
        );
    }
    let mut segments = Vec::new();
    let mut numbers = String::new();
    for (i, block) in text.split(LINE).skip(1).enumerate() {
        let line = i + 1;
        let body = &block[..block
            .find("</object>")
            .ok_or_else(|| format!("line object {line}: its <object> is not closed"))?];
        // type, x0, y0, x1, y1
        let mut values = ["0"; 5];
        for property in body.split("<void property=\"").skip(1) {
            let (name, rest) = property
                .split_once('"')
                .ok_or_else(|| format!("line object {line}: a property without a name"))?;
            let slot = match name {
                "type" => 0,
                "x0" => 1,
                "y0" => 2,
                "x1" => 3,
                "y1" => 4,
                _ => continue,
            };
            values[slot] = value_of(rest).ok_or_else(|| {
                format!("line object {line}: property {name} has no <int> or <double> value")
            })?;
        }
        let assignment = line_type(values[0]).ok_or_else(|| {
            format!(
                "line object {line}: unknown line type {} (expected 0–4)",
                crate::limits::short_text(values[0])
            )
        })?;
        let mut xy = [0.0; 4];
        for (k, v) in values[1..].iter().enumerate() {
            xy[k] = v
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    format!(
                        "line object {line}: coordinate \"{}\" is not a finite number",
                        crate::limits::short_text(v)
                    )
                })?;
            numbers.push_str(v);
            numbers.push(' ');
        }
        segments.push(Segment {
            a: Vec2::new(xy[0], xy[1]),
            b: Vec2::new(xy[2], xy[3]),
            assignment,
            fold_angle: assignment.default_target(),
        });
    }
    if segments.is_empty() {
        return Err("no oripa.OriLineProxy lines in the document".into());
    }
    mesh_of_lines(&segments, notes, super::decimal_quantum(&numbers))
}

/// The text of the first `<int>` or `<double>` element in `rest`, trimmed.
fn value_of(rest: &str) -> Option<&str> {
    let start = rest.find('>')? + 1;
    let rest = &rest[start..];
    let open = rest.find('<')?;
    let tag_end = rest[open..].find('>')? + open + 1;
    let tag = &rest[open..tag_end];
    if tag != "<int>" && tag != "<double>" {
        return None;
    }
    let close = rest[tag_end..].find('<')? + tag_end;
    Some(rest[tag_end..close].trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(t: i32, x0: f64, y0: f64, x1: f64, y1: f64) -> String {
        format!(
            r#"<void index="0"><object class="oripa.OriLineProxy">
 <void property="type"><int>{t}</int></void>
 <void property="x0"><double>{x0}</double></void>
 <void property="x1"><double>{x1}</double></void>
 <void property="y0"><double>{y0}</double></void>
 <void property="y1"><double>{y1}</double></void>
</object></void>"#
        )
    }

    #[test]
    fn a_square_with_one_valley_diagonal_reads_as_two_triangles() {
        let doc = format!(
            "<?xml version=\"1.0\"?><java class=\"java.beans.XMLDecoder\">{}{}{}{}{}</java>",
            line(1, 0.0, 0.0, 10.0, 0.0),
            line(1, 10.0, 0.0, 10.0, 10.0),
            line(1, 10.0, 10.0, 0.0, 10.0),
            line(1, 0.0, 10.0, 0.0, 0.0),
            line(3, 0.0, 0.0, 10.0, 10.0),
        );
        let mesh = parse(&doc, &mut Vec::new()).unwrap();
        assert_eq!(mesh.faces().len(), 2);
        let valleys = mesh
            .edges()
            .iter()
            .filter(|e| e.assignment == crate::mesh::Assignment::Valley)
            .count();
        assert_eq!(valleys, 1);
    }

    #[test]
    fn a_bad_type_or_coordinate_is_named() {
        let doc = format!(
            "<java class=\"java.beans.XMLDecoder\">{}</java>",
            line(9, 0.0, 0.0, 1.0, 1.0)
        );
        let e = parse(&doc, &mut Vec::new()).unwrap_err().to_string();
        assert!(
            e.contains("line object 1") && e.contains("unknown line type 9"),
            "{e}"
        );
        let doc = "<java class=\"java.beans.XMLDecoder\"><object class=\"oripa.OriLineProxy\"><void property=\"x0\"><double>NaN</double></void></object></java>";
        let e = parse(doc, &mut Vec::new()).unwrap_err().to_string();
        assert!(e.contains("not a finite number"), "{e}");
        let e = parse("<html/>", &mut Vec::new()).unwrap_err().to_string();
        assert!(e.contains("not an ORIPA .opx document"), "{e}");
    }
}
