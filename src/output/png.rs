//! Pictures for a person, not a machine: `sheet.png`, the toolpath as the cutter will cut
//! it (every dash as it is, at a width that shows, in the operation colours of
//! [`super::colour`], on the media), and `design.png`, the 3D form shaded with its
//! creases coloured. Drawn with `tiny-skia` (no GPU, no system libraries).

use crate::fab::{LineKind, Toolpath};
use crate::mesh::{Mesh, Vec3};
use tiny_skia::{Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// Longest side of either picture, px: sharp on a screen, a few hundred kB at most.
pub const MAX_SIDE_PX: f64 = 2400.0;

/// Resolution of `sheet.png`, px per mm: 4, less where the media is larger than
/// [`MAX_SIDE_PX`] allows.
pub fn sheet_px_per_mm(path: &Toolpath) -> f64 {
    (MAX_SIDE_PX / path.media.width.max(path.media.height)).min(4.0)
}

/// Width of every stroke in `sheet.png`, px: half a millimetre, at least 2 px.
pub fn sheet_stroke_px(px_per_mm: f64) -> f64 {
    (0.5 * px_per_mm).round().max(2.0)
}

fn paint(rgb: [u8; 3], anti_alias: bool) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    p.anti_alias = anti_alias;
    p
}

/// `sheet.png`: the media white with a grey edge, every stroke of the toolpath in its
/// kind's colour, [`sheet_stroke_px`] wide with butt ends. Not anti-aliased, so every
/// pixel is one of those colours and a reader can count what each operation covers.
pub fn sheet(path: &Toolpath) -> Result<Vec<u8>, String> {
    let s = sheet_px_per_mm(path);
    let (w, h) = (path.media.width * s, path.media.height * s);
    let mut pixmap = Pixmap::new(w.ceil() as u32, h.ceil() as u32)
        .ok_or_else(|| format!("a {w:.0} × {h:.0} px preview is too large"))?;
    pixmap.fill(Color::WHITE);
    if let Some(edge) =
        Rect::from_xywh(0.5, 0.5, w as f32 - 1.0, h as f32 - 1.0).map(PathBuilder::from_rect)
    {
        let thin = Stroke {
            width: 1.0,
            ..Stroke::default()
        };
        pixmap.stroke_path(
            &edge,
            &paint([154, 154, 154], false),
            &thin,
            Transform::identity(),
            None,
        );
    }
    let stroke = Stroke {
        width: sheet_stroke_px(s) as f32,
        line_cap: LineCap::Butt,
        ..Stroke::default()
    };
    // Scores first, the outline over them, as the kinds are cut.
    for kind in LineKind::ALL {
        let mut pb = PathBuilder::new();
        for st in path.strokes.iter().filter(|st| st.kind == kind) {
            // The sheet's y grows up, the picture's down.
            let px = |p: crate::mesh::Vec2| ((p.x * s) as f32, (h - p.y * s) as f32);
            let (x, y) = px(st.from);
            pb.move_to(x, y);
            let (x, y) = px(st.to);
            match st.bend.map(|c| c.map(px)) {
                Some([(x1, y1), (x2, y2)]) => pb.cubic_to(x1, y1, x2, y2, x, y),
                None => pb.line_to(x, y),
            }
        }
        if let Some(p) = pb.finish() {
            let colour = super::colour::rgb(kind);
            pixmap.stroke_path(
                &p,
                &paint(colour, false),
                &stroke,
                Transform::identity(),
                None,
            );
        }
    }
    pixmap.encode_png().map_err(|e| format!("sheet.png: {e}"))
}

/// Size of `design.png`, px.
pub const DESIGN_SIZE_PX: [u32; 2] = [1200, 900];

/// The direction `design.png` looks from (towards the form), unit: from the front, to the
/// right and above, so a sheet lying in the xy-plane shows its top at a slant.
pub fn design_view() -> Vec3 {
    Vec3::new(0.45, -0.75, 0.85).normalize()
}

/// The orthographic camera of `design.png`: right and up axes on the screen, and the
/// scale (px per mm) and centre that fit the form with 6% to spare on every side.
pub struct DesignCamera {
    /// Screen x in space.
    pub right: Vec3,
    /// Screen up in space.
    pub up: Vec3,
    /// Pixels per mm.
    pub px_per_mm: f64,
    /// The point of space drawn at the picture's centre.
    pub centre: Vec3,
    /// The picture's width and height, px.
    pub size_px: [u32; 2],
}

/// How far above the horizon `design-side.png` looks from, radians: enough to show the
/// top of a corrugation, little enough to keep the profile.
const SIDE_ELEVATION: f64 = 12.0 * std::f64::consts::PI / 180.0;

/// The direction `design-side.png` looks from: level with the form (raised by
/// `SIDE_ELEVATION`) along the horizontal direction in which it shows least of its
/// paper, so a sheet bent about one axis is seen along that axis, its profile drawn: an
/// arch, invisible from above, shows as an arch. Of 24 directions 7.5° apart, the one
/// with the smallest Σ area·|n·d| over the faces.
pub fn design_side_view(mesh: &Mesh) -> Vec3 {
    let x = mesh.positions();
    let shown = |d: Vec3| -> f64 {
        mesh.faces()
            .iter()
            .map(|&[a, b, c]| (x[b] - x[a]).cross(&(x[c] - x[a])).dot(&d).abs())
            .sum()
    };
    let horizontal = (0..24)
        .map(|k| {
            let t = f64::from(k) * std::f64::consts::PI / 24.0;
            Vec3::new(t.cos(), t.sin(), 0.0)
        })
        .min_by(|a, b| shown(*a).total_cmp(&shown(*b)))
        .expect("directions");
    // From the side where the picture's right is the form's +x or +y, whichever it faces.
    let d = if horizontal.x + horizontal.y < 0.0 {
        -horizontal
    } else {
        horizontal
    };
    (d * SIDE_ELEVATION.cos() + Vec3::z() * SIDE_ELEVATION.sin()).normalize()
}

impl DesignCamera {
    /// Frames `points` seen from [`design_view`].
    pub fn framing(points: &[Vec3]) -> DesignCamera {
        DesignCamera::framing_from(points, design_view())
    }

    /// Frames `points` seen from `view` (a unit vector, not vertical).
    pub fn framing_from(points: &[Vec3], view: Vec3) -> DesignCamera {
        DesignCamera::framing_sized(points, view, DESIGN_SIZE_PX)
    }

    /// Frames `points` seen from `view` in a picture of `size_px`.
    pub fn framing_sized(points: &[Vec3], view: Vec3, size_px: [u32; 2]) -> DesignCamera {
        let right = Vec3::z().cross(&view).normalize();
        let up = view.cross(&right);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for (k, axis) in [right, up].iter().enumerate() {
                lo[k] = lo[k].min(p.dot(axis));
                hi[k] = hi[k].max(p.dot(axis));
            }
        }
        let [pw, ph] = size_px.map(f64::from);
        let span = [(hi[0] - lo[0]).max(1e-9), (hi[1] - lo[1]).max(1e-9)];
        let px_per_mm = (0.88 * pw / span[0]).min(0.88 * ph / span[1]);
        let centre = right * (lo[0] + hi[0]) / 2.0 + up * (lo[1] + hi[1]) / 2.0;
        DesignCamera {
            right,
            up,
            px_per_mm,
            centre,
            size_px,
        }
    }

    /// Where `p` is drawn, px from the top-left corner.
    pub fn screen(&self, p: Vec3) -> (f32, f32) {
        let [pw, ph] = self.size_px.map(f64::from);
        let d = p - self.centre;
        (
            (pw / 2.0 + d.dot(&self.right) * self.px_per_mm) as f32,
            (ph / 2.0 - d.dot(&self.up) * self.px_per_mm) as f32,
        )
    }
}

/// Colour of the background of `design.png`.
pub const DESIGN_BACKGROUND: [u8; 3] = [251, 250, 247];

/// `design.png`: the 3D form from [`design_view`], faces painted far to near (the
/// painter's order), each shaded by how squarely it faces the light (paper colour, both
/// sides alike) with its mountain and valley creases drawn over it in their colours, so
/// nearer paper hides the creases behind it.
pub fn design(mesh: &Mesh) -> Result<Vec<u8>, String> {
    design_from(mesh, design_view()).map_err(|e| format!("design.png: {e}"))
}

/// `design-side.png`: the same picture from [`design_side_view`].
pub fn design_side(mesh: &Mesh) -> Result<Vec<u8>, String> {
    design_from(mesh, design_side_view(mesh)).map_err(|e| format!("design-side.png: {e}"))
}

/// The 3D form seen from `view` (see [`design`]).
fn design_from(mesh: &Mesh, view: Vec3) -> Result<Vec<u8>, String> {
    let x = mesh.positions();
    let camera = DesignCamera::framing_from(x, view);
    paint_design(mesh, x, &camera, view)?
        .encode_png()
        .map_err(|e| e.to_string())
}

/// Size of one frame of `motion.png`, px.
pub const MOTION_SIZE_PX: [u32; 2] = [600, 450];

/// Milliseconds each frame of `motion.png` shows, and the last one (the design) longer.
pub const MOTION_FRAME_MS: u16 = 67;
/// How long `motion.png` holds the design before it plays again.
pub const MOTION_HOLD_MS: u16 = 1500;

/// `motion.png`: an animated PNG (APNG, which every browser plays) of `frames`, each
/// every vertex of `sheet` placed (mm), painted as [`design`] paints the design, seen
/// from [`motion_view`] by one camera framing every frame, so the sheet does not jump.
/// It plays on a loop and holds the last frame; a viewer without APNG shows frame 0.
pub fn motion(sheet: &Mesh, frames: &[Vec<Vec3>]) -> Result<Vec<u8>, String> {
    let (camera, view) = motion_camera(sheet, frames.iter().map(Vec::as_slice), MOTION_SIZE_PX);
    let [w, h] = MOTION_SIZE_PX;
    let mut bytes = Vec::new();
    {
        let mut encoder = ::png::Encoder::new(&mut bytes, w, h);
        encoder.set_color(::png::ColorType::Rgba);
        encoder.set_depth(::png::BitDepth::Eight);
        let count = u32::try_from(frames.len()).map_err(|_| "too many frames")?;
        encoder
            .set_animated(count.max(1), 0)
            .map_err(|e| format!("motion.png: {e}"))?;
        let mut writer = encoder
            .write_header()
            .map_err(|e| format!("motion.png: {e}"))?;
        for (k, x) in frames.iter().enumerate() {
            let delay = if k + 1 == frames.len() {
                MOTION_HOLD_MS
            } else {
                MOTION_FRAME_MS
            };
            writer
                .set_frame_delay(delay, 1000)
                .map_err(|e| format!("motion.png: {e}"))?;
            // Opaque throughout, so tiny-skia's premultiplied pixels are plain RGBA.
            let pixmap = paint_design(sheet, x, &camera, view)?;
            writer
                .write_image_data(pixmap.data())
                .map_err(|e| format!("motion.png: {e}"))?;
        }
        writer.finish().map_err(|e| format!("motion.png: {e}"))?;
    }
    Ok(bytes)
}

/// The one direction a motion is seen from: [`design_view`], unless the sheet shows
/// less than a third of its paper there in some frame (a sheet whose design lies on its
/// side is seen edge-on when flat) and another of 36 directions (every 30° round, 20°,
/// 45° and 70° up) shows more of it in its worst frame. What a frame shows of its
/// paper is Σ|n·d|·area over Σ area, the faces' projected share.
pub fn motion_view<'a>(sheet: &Mesh, frames: impl Iterator<Item = &'a [Vec3]> + Clone) -> Vec3 {
    let shown = |d: Vec3| -> f64 {
        frames
            .clone()
            .map(|x| {
                let (mut seen, mut area) = (0.0, 0.0);
                for &[a, b, c] in sheet.faces() {
                    let n = (x[b] - x[a]).cross(&(x[c] - x[a]));
                    seen += n.dot(&d).abs();
                    area += n.norm();
                }
                if area > 0.0 {
                    seen / area
                } else {
                    1.0
                }
            })
            .fold(1.0, f64::min)
    };
    let preferred = design_view();
    if shown(preferred) >= 1.0 / 3.0 {
        return preferred;
    }
    let around = (0..12).flat_map(|k| {
        let azimuth = f64::from(k) * std::f64::consts::PI / 6.0;
        [20.0_f64, 45.0, 70.0].map(|e| {
            let e = e.to_radians();
            Vec3::new(azimuth.cos() * e.cos(), azimuth.sin() * e.cos(), e.sin())
        })
    });
    std::iter::once(preferred)
        .chain(around)
        .map(|d| (shown(d), d))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(preferred, |(_, d)| d)
}

/// The one camera and view a motion's pictures share ([`motion_view`]), framing every
/// frame in a picture of `size_px`.
fn motion_camera<'a>(
    sheet: &Mesh,
    frames: impl Iterator<Item = &'a [Vec3]> + Clone,
    size_px: [u32; 2],
) -> (DesignCamera, Vec3) {
    let all: Vec<Vec3> = frames.clone().flatten().copied().collect();
    let view = motion_view(sheet, frames);
    (DesignCamera::framing_sized(&all, view, size_px), view)
}

/// A picture as plain pixels: opaque RGB, 8 bits a channel, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// `width × height` pixels of three bytes each.
    pub rgb: Vec<u8>,
}

/// Still pictures of `frames` of a motion (each every vertex of `sheet` placed, mm),
/// painted as [`motion`] paints them: seen from [`motion_view`] by one camera framing
/// all of them, so their sizes and positions compare, each `size_px`.
pub fn stills(sheet: &Mesh, frames: &[&[Vec3]], size_px: [u32; 2]) -> Result<Vec<Picture>, String> {
    let (camera, view) = motion_camera(sheet, frames.iter().copied(), size_px);
    frames
        .iter()
        .map(|x| {
            let pixmap = paint_design(sheet, x, &camera, view)?;
            // Opaque throughout, so the premultiplied pixels are the plain colours.
            let rgb = pixmap
                .data()
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            Ok(Picture {
                width: pixmap.width(),
                height: pixmap.height(),
                rgb,
            })
        })
        .collect()
}

/// `mesh` with its vertices at `x`, painted far to near from `view` (see [`design`]).
fn paint_design(
    mesh: &Mesh,
    x: &[Vec3],
    camera: &DesignCamera,
    view: Vec3,
) -> Result<Pixmap, String> {
    let light = (view + Vec3::new(-0.3, 0.2, 0.4)).normalize();
    let [pw, ph] = camera.size_px;
    let mut pixmap = Pixmap::new(pw, ph).ok_or("no pixmap")?;
    let [r, g, b] = DESIGN_BACKGROUND;
    pixmap.fill(Color::from_rgba8(r, g, b, 255));
    let topo = mesh.topology();
    let faces = mesh.faces();
    let mut order: Vec<usize> = (0..faces.len()).collect();
    let depth = |f: usize| faces[f].iter().map(|&v| x[v].dot(&view)).sum::<f64>();
    // Far first: a point further along the view direction is nearer the viewer.
    order.sort_by(|&a, &b| depth(a).total_cmp(&depth(b)));
    let crease = Stroke {
        width: 2.0,
        line_cap: LineCap::Round,
        ..Stroke::default()
    };
    let edges = mesh.edges();
    let kinds = LineKind::of_mesh(mesh);
    for f in order {
        let [a, b, c] = faces[f];
        let n = (x[b] - x[a]).cross(&(x[c] - x[a]));
        let lit = if n.norm() > 0.0 {
            n.normalize().dot(&light).abs()
        } else {
            0.0
        };
        let shade = 0.45 + 0.55 * lit;
        let tone = [241.0, 231.0, 208.0].map(|c: f64| (c * shade).round() as u8);
        let mut pb = PathBuilder::new();
        let (sa, sb, sc) = (
            camera.screen(x[a]),
            camera.screen(x[b]),
            camera.screen(x[c]),
        );
        pb.move_to(sa.0, sa.1);
        pb.line_to(sb.0, sb.1);
        pb.line_to(sc.0, sc.1);
        pb.close();
        if let Some(p) = pb.finish() {
            pixmap.fill_path(
                &p,
                &paint(tone, true),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
        for &e in &topo.face_edges[f] {
            let kind = kinds[e];
            if kind == LineKind::Flat {
                continue;
            }
            let [u, v] = edges[e].vertices;
            let (su, sv) = (camera.screen(x[u]), camera.screen(x[v]));
            let mut pb = PathBuilder::new();
            pb.move_to(su.0, su.1);
            pb.line_to(sv.0, sv.1);
            if let Some(p) = pb.finish() {
                let colour = super::colour::rgb(kind);
                pixmap.stroke_path(
                    &p,
                    &paint(colour, true),
                    &crease,
                    Transform::identity(),
                    None,
                );
            }
        }
    }
    Ok(pixmap)
}
