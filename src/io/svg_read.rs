//! Origami Simulator SVG crease patterns: stroke colour gives the crease type, opacity the
//! fold angle (REFERENCE.md). SVG user units become millimetres through the root's width
//! and viewBox (96 px per inch when no unit is given); the y axis is flipped so the
//! pattern reads the same way up in crease's y-up coordinates.

use super::planar::{mesh_from_segments, PlanarReport, Segment};
use super::svg_path::flatten_path;
use super::svg_transform::{number_list, parse_transform, Affine};
use super::FileCause;
use crate::mesh::{split_along_cuts, Assignment, Mesh, Vec2};
use std::f64::consts::PI;
use svg::node::element::tag::Type;
use svg::parser::Event;

/// Millimetres per CSS pixel.
const MM_PER_PX: f64 = 25.4 / 96.0;

#[derive(Clone)]
struct Style {
    stroke: Option<String>,
    opacity: f64,
    stroke_opacity: f64,
    transform: Affine,
    hidden: bool,
}

/// Parses a colour to RGB: `#rgb`, `#rrggbb`, `rgb(r, g, b)` (numbers or percentages), or
/// a CSS name among those crease patterns use.
pub fn parse_colour(text: &str) -> Option<[u8; 3]> {
    let t = text.trim().to_ascii_lowercase();
    if let Some(hex) = t.strip_prefix('#') {
        let v = |s: &str| u8::from_str_radix(s, 16).ok();
        return match hex.len() {
            3 => {
                let d: Vec<u8> = hex
                    .chars()
                    .map(|c| c.to_digit(16).map(|x| x as u8 * 17))
                    .collect::<Option<_>>()?;
                Some([d[0], d[1], d[2]])
            }
            6 => Some([v(&hex[0..2])?, v(&hex[2..4])?, v(&hex[4..6])?]),
            _ => None,
        };
    }
    if let Some(inner) = t.strip_prefix("rgb(").and_then(|s| s.strip_suffix(')')) {
        let parts: Vec<u8> = inner
            .split(',')
            .map(|p| {
                let p = p.trim();
                match p.strip_suffix('%') {
                    Some(pc) => pc
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .map(|x| (x * 2.55).round() as u8),
                    None => p
                        .parse::<f64>()
                        .ok()
                        .map(|x| x.round().clamp(0.0, 255.0) as u8),
                }
            })
            .collect::<Option<_>>()?;
        return (parts.len() == 3).then(|| [parts[0], parts[1], parts[2]]);
    }
    Some(match t.as_str() {
        "black" => [0, 0, 0],
        "white" => [255, 255, 255],
        "red" => [255, 0, 0],
        "lime" => [0, 255, 0],
        "green" => [0, 128, 0],
        "blue" => [0, 0, 255],
        "yellow" => [255, 255, 0],
        "magenta" | "fuchsia" => [255, 0, 255],
        "cyan" | "aqua" => [0, 255, 255],
        "gray" | "grey" => [128, 128, 128],
        _ => return None,
    })
}

/// The crease type of an exact Origami Simulator colour, or grey (`gray`, `#808080`): the
/// auxiliary lines Flat-Folder and ORIPA-like tools draw, flat.
pub fn assignment_of_colour(rgb: [u8; 3]) -> Option<Assignment> {
    Some(match rgb {
        [0, 0, 0] => Assignment::Boundary,
        [255, 0, 0] => Assignment::Mountain,
        [0, 0, 255] => Assignment::Valley,
        [0, 255, 0] => Assignment::Cut,
        [255, 255, 0] => Assignment::Flat,
        // Flat-Folder's and ORIPA-like tools' auxiliary lines.
        [128, 128, 128] => Assignment::Flat,
        [255, 0, 255] => Assignment::Unassigned,
        _ => return None,
    })
}

fn length_mm(text: &str) -> Option<f64> {
    let t = text.trim();
    let split = t
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(t.len());
    let value: f64 = t[..split].trim().parse().ok()?;
    let unit = match &t[split..] {
        "" | "px" => MM_PER_PX,
        "mm" => 1.0,
        "cm" => 10.0,
        "in" => 25.4,
        "pt" => 25.4 / 72.0,
        "pc" => 25.4 / 6.0,
        _ => return None,
    };
    Some(value * unit)
}

/// The root's `width` in mm: absent or a percentage (the page decides) is `None`, with a
/// note for the percentage; a negative, zero, non-numeric or unknown-unit width is an error,
/// since every length of the pattern is scaled by it.
fn root_width(text: Option<&str>, notes: &mut Vec<String>) -> Result<Option<f64>, String> {
    let Some(text) = text else { return Ok(None) };
    if text.trim().ends_with('%') {
        notes.push(format!(
            "the root width is \"{}\", relative to a page: user units are read as px (96 per inch)",
            crate::limits::short_text(text)
        ));
        return Ok(None);
    }
    match length_mm(text) {
        Some(w) if w.is_finite() && w > 0.0 => Ok(Some(w)),
        Some(_) => Err(format!(
            "the root width \"{}\" must be a positive length",
            crate::limits::short_text(text).escape_debug()
        )),
        None => Err(format!(
            "the root width \"{}\" is not a length (a number with mm, cm, in, pt, pc or px)",
            crate::limits::short_text(text).escape_debug()
        )),
    }
}

fn style_property(style: &str, name: &str) -> Option<String> {
    style.split(';').find_map(|decl| {
        let (k, v) = decl.split_once(':')?;
        (k.trim() == name).then(|| v.trim().to_string())
    })
}

/// Records what planar import changed as notes for the user.
pub fn report_notes(report: &PlanarReport, notes: &mut Vec<String>) {
    if report.dangling_removed > 0 {
        notes.push(format!(
            "dropped {} line piece(s) that end in open paper and bound no face",
            report.dangling_removed
        ));
    }
    if report.holes > 0 {
        notes.push(format!("{} hole(s) cut out of the paper", report.holes));
    }
}

/// An element's attributes, as the `svg` crate's parser gives them.
type Attributes = std::collections::HashMap<String, svg::node::Value>;

/// Reads an Origami Simulator style SVG (stroke colour gives the crease type, opacity
/// the fold angle) into a mesh in mm, with notes on anything read by assumption.
pub fn parse(text: &str, notes: &mut Vec<String>) -> Result<Mesh, FileCause> {
    if text.trim().is_empty() {
        return Err("the file is empty".into());
    }
    let drawing = Drawing::read(text, notes)?;
    let mut mesh = sheet_of(&drawing.segments, notes)?;
    // A point of a relative path command adds a rounded offset to a rounded start: twice
    // the rounding of one number.
    mesh.coordinate_precision = super::rounding_of(
        &mesh,
        2.0 * super::decimal_quantum(&drawing.geometry_text) * drawing.root_scale,
    );
    Ok(mesh)
}

/// The paper the lines draw, green read as Origami Simulator's cut — unless those cuts
/// fall the sheet apart into pieces and the same lines read as unassigned creases hold it
/// together in fewer: a crease pattern is folded from one sheet, and Flat-Folder, whose
/// examples draw unassigned creases `#00FF00`, reads a colour it does not know as
/// unassigned. A note says which reading was taken and why.
fn sheet_of(segments: &[Segment], notes: &mut Vec<String>) -> Result<Mesh, FileCause> {
    let greens = segments
        .iter()
        .filter(|s| s.assignment == Assignment::Cut)
        .count();
    let as_cuts = paper_cut_along(segments);
    let pieces = |m: &Mesh| m.shape().components;
    let cut_pieces = match &as_cuts {
        Ok((mesh, _)) if greens > 0 => pieces(mesh),
        _ => 0,
    };
    if cut_pieces > 1 {
        let creases: Vec<Segment> = segments
            .iter()
            .map(|s| match s.assignment {
                Assignment::Cut => Segment {
                    assignment: Assignment::Unassigned,
                    fold_angle: 0.0,
                    ..s.clone()
                },
                _ => s.clone(),
            })
            .collect();
        if let Ok((mesh, report)) = paper_cut_along(&creases) {
            if pieces(&mesh) < cut_pieces {
                notes.push(format!(
                    "the {greens} green line(s) are read as unassigned creases, as Flat-Folder reads them: \
                     as Origami Simulator's cuts they would cut the sheet into {cut_pieces} pieces"
                ));
                report_notes(&report, notes);
                return Ok(mesh);
            }
        }
    }
    let (mesh, report) = as_cuts?;
    report_notes(&report, notes);
    Ok(mesh)
}

/// The mesh the lines draw, split along its cuts.
fn paper_cut_along(segments: &[Segment]) -> Result<(Mesh, PlanarReport), FileCause> {
    let (mut parts, report) = mesh_from_segments(segments)?;
    split_along_cuts(&mut parts);
    Ok((Mesh::new(parts)?, report))
}

/// What an SVG's visible crease elements draw.
struct Drawing {
    /// Straight crease segments in mm.
    segments: Vec<Segment>,
    /// The root's user unit in mm.
    root_scale: f64,
    /// The coordinate attributes of the creases: only they tell the drawing's rounding
    /// (metadata carries other precisions).
    geometry_text: String,
}

impl Drawing {
    /// Walks the elements, inheriting style and transforms down the tree.
    fn read(text: &str, notes: &mut Vec<String>) -> Result<Drawing, String> {
        let parser = svg::read(text).map_err(|e| format!("not readable as SVG: {e}"))?;
        let mut stack: Vec<Style> = Vec::new();
        let root_style = Style {
            stroke: None,
            opacity: 1.0,
            stroke_opacity: 1.0,
            transform: Affine::IDENTITY,
            hidden: false,
        };
        let mut drawing = Drawing {
            segments: Vec::new(),
            root_scale: MM_PER_PX,
            geometry_text: String::new(),
        };
        let mut saw_svg = false;
        for (element_index, event) in parser.enumerate() {
            let (name, kind, attrs) = match event {
                Event::Tag(name, kind, attrs) => (name, kind, attrs),
                Event::Error(e) => return Err(format!("not readable as SVG: {e}")),
                _ => continue,
            };
            if kind == Type::End {
                stack.pop();
                continue;
            }
            let parent = stack.last().unwrap_or(&root_style);
            let mut style = inherited_style(parent, name, &attrs)?;
            if name == "svg" && !saw_svg {
                saw_svg = true;
                drawing.root_scale = root_units(&attrs, notes)?;
                // User units to mm, then flip y.
                let k = drawing.root_scale;
                style.transform = Affine([k, 0.0, 0.0, -k, 0.0, 0.0]);
            }
            if let Some(t) = attrs.get("transform") {
                style.transform = style.transform.then_inner(&parse_transform(t)?);
            }
            if kind == Type::Start {
                stack.push(style.clone());
            }
            drawing.add_shape(name, element_index, &attrs, &style)?;
        }
        if !saw_svg {
            return Err("no <svg> element: not an SVG file".into());
        }
        if !stack.is_empty() {
            return Err(format!(
                "the file ends inside {} open element(s): it was cut short",
                stack.len()
            ));
        }
        Ok(drawing)
    }

    /// Adds the segments of element `name` if it is a visible crease shape.
    fn add_shape(
        &mut self,
        name: &str,
        element_index: usize,
        attrs: &Attributes,
        style: &Style,
    ) -> Result<(), String> {
        let shapes = ["line", "rect", "polygon", "polyline", "path"];
        if style.hidden || !shapes.contains(&name) {
            return Ok(());
        }
        let Some((assignment, fold_angle)) = crease_of(name, element_index, style)? else {
            return Ok(());
        };
        for k in [
            "d", "x1", "y1", "x2", "y2", "x", "y", "width", "height", "points",
        ] {
            if let Some(v) = attrs.get(k) {
                self.geometry_text.push_str(v);
                self.geometry_text.push(' ');
            }
        }
        for line in shape_polylines(name, element_index, attrs, &style.transform)? {
            for w in line.windows(2) {
                self.segments.push(Segment {
                    a: w[0],
                    b: w[1],
                    assignment,
                    fold_angle,
                });
            }
        }
        Ok(())
    }
}

/// An element's style: its parent's, with the element's own stroke, opacities and
/// display (from its `style` attribute or presentation attributes); what never draws
/// (definitions, clip paths, masks, symbols, markers, patterns) is hidden.
fn inherited_style(parent: &Style, name: &str, attrs: &Attributes) -> Result<Style, String> {
    let style_attr = attrs
        .get("style")
        .map(|v| v.to_string())
        .unwrap_or_default();
    let prop =
        |k: &str| style_property(&style_attr, k).or_else(|| attrs.get(k).map(|v| v.to_string()));
    let mut style = parent.clone();
    if let Some(s) = prop("stroke") {
        style.stroke = Some(s);
    }
    // A fold angle is scaled by these: NaN, infinite or out-of-range values are refused
    // here, not carried into a crease at NaN°.
    let opacity = |key: &str, o: String| {
        let value = o
            .trim()
            .parse::<f64>()
            .map_err(|_| format!("<{name}>: bad {key} \"{}\"", crate::limits::short_text(&o)))?;
        crate::limits::OPACITY
            .check(format!("<{name}> {key}"), value)
            .map_err(|e| e.to_string())
    };
    if let Some(o) = prop("opacity") {
        style.opacity *= opacity("opacity", o)?;
    }
    if let Some(o) = prop("stroke-opacity") {
        style.stroke_opacity = opacity("stroke-opacity", o)?;
    }
    if prop("display").as_deref() == Some("none") {
        style.hidden = true;
    }
    if matches!(
        name,
        "defs" | "clipPath" | "mask" | "symbol" | "marker" | "pattern"
    ) {
        style.hidden = true;
    }
    Ok(style)
}

/// Millimetres per user unit of the root `<svg>`: its width over its viewBox's width, or
/// CSS pixels when either is missing.
fn root_units(attrs: &Attributes, notes: &mut Vec<String>) -> Result<f64, String> {
    let view: Option<Vec<f64>> = attrs.get("viewBox").map(|v| {
        v.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .filter_map(|s| s.parse().ok())
            .collect()
    });
    let width = root_width(attrs.get("width").map(|v| v.to_string()).as_deref(), notes)?;
    if let Some(&[_, _, w, h]) = view.as_deref() {
        if !(w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite()) {
            return Err(format!(
                "the root viewBox has a width of {w} and a height of {h}: both must be positive"
            ));
        }
    }
    // The viewBox origin only frames the picture; coordinates keep their origin so a
    // pattern written by crease reads back in place.
    Ok(match (view.as_deref(), width) {
        (Some([_, _, w, _]), Some(wmm)) => wmm / w,
        _ => MM_PER_PX,
    })
}

/// The crease a stroked shape draws: its assignment by stroke colour, and its fold angle
/// (the paper's sign: mountain +π) scaled by opacity; `None` for a shape with no stroke.
fn crease_of(
    name: &str,
    element_index: usize,
    style: &Style,
) -> Result<Option<(Assignment, f64)>, String> {
    let stroke = match style.stroke.as_deref() {
        None | Some("none") => return Ok(None),
        Some(s) => s,
    };
    let rgb = parse_colour(stroke).ok_or_else(|| {
        format!(
            "<{name}> (element {element_index}) has an unreadable stroke colour \"{}\"",
            crate::limits::short_text(stroke).escape_debug()
        )
    })?;
    let assignment = assignment_of_colour(rgb).ok_or_else(|| {
        format!(
            "<{name}> (element {element_index}) has stroke colour \"{}\", which is not a crease colour \
             (black border, red mountain, blue valley, green cut, yellow or grey flat, magenta unassigned)",
            crate::limits::short_text(stroke)
        )
    })?;
    let fold_angle = match assignment {
        Assignment::Mountain => PI * style.opacity * style.stroke_opacity,
        Assignment::Valley => -PI * style.opacity * style.stroke_opacity,
        _ => 0.0,
    };
    Ok(Some((assignment, fold_angle)))
}

/// The polylines a `line`, `rect`, `polygon`, `polyline` or `path` draws, through `m`.
fn shape_polylines(
    name: &str,
    element_index: usize,
    attrs: &Attributes,
    m: &Affine,
) -> Result<Vec<Vec<Vec2>>, String> {
    let get = |k: &str| attrs.get(k).map(|v| v.to_string());
    let num = |k: &str| -> Result<f64, String> {
        match get(k) {
            None => Ok(0.0),
            Some(v) => v.trim().trim_end_matches("px").parse().map_err(|_| {
                format!(
                    "<{name}> (element {element_index}) has a bad {k} \"{}\"",
                    crate::limits::short_text(&v)
                )
            }),
        }
    };
    Ok(match name {
        "line" => vec![vec![
            m.apply(Vec2::new(num("x1")?, num("y1")?)),
            m.apply(Vec2::new(num("x2")?, num("y2")?)),
        ]],
        "rect" => {
            let (x, y, w, h) = (num("x")?, num("y")?, num("width")?, num("height")?);
            let c = [(x, y), (x + w, y), (x + w, y + h), (x, y + h), (x, y)];
            vec![c.iter().map(|&(a, b)| m.apply(Vec2::new(a, b))).collect()]
        }
        "polygon" | "polyline" => {
            let values = number_list(
                &get("points").unwrap_or_default(),
                &format!("<{name}> points"),
            )?;
            let mut pts: Vec<Vec2> = values
                .chunks_exact(2)
                .map(|c| m.apply(Vec2::new(c[0], c[1])))
                .collect();
            if name == "polygon" && !pts.is_empty() {
                pts.push(pts[0]);
            }
            vec![pts]
        }
        _ => flatten_path(&get("d").unwrap_or_default(), m)
            .map_err(|e| format!("<path> (element {element_index}): {e}"))?,
    })
}
