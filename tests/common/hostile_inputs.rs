//! Drawings built to cost the reader what no crease pattern does, shared by the command
//! line's and the studio's hostile-input tests (each checks its own face refuses them).

/// A FOLD crease pattern of one face of `n` corners on a circle of 100 mm, every other
/// corner at `inner` of the radius (1 for a plain circle, below 1 for a sawtooth): ear
/// clipping is quadratic in a face's corners (30,000 took 18 s).
pub fn one_face_fold(n: usize, inner: f64) -> String {
    let coords: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let r = if i % 2 == 0 { 100.0 } else { 100.0 * inner };
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    serde_json::json!({
        "file_spec": 1.1,
        "frame_classes": ["creasePattern"],
        "vertices_coords": coords,
        "edges_vertices": (0..n).map(|i| [i, (i + 1) % n]).collect::<Vec<_>>(),
        "edges_assignment": vec!["B"; n],
        "faces_vertices": [(0..n).collect::<Vec<_>>()],
    })
    .to_string()
}

/// A pseudo-random number below `n` for index `k` and stream `m` (a fixed scramble: the
/// same drawing on every run).
fn scrambled(k: u64, m: u64, n: u64) -> u64 {
    ((k * 7919 + m * 104_729) * (m + 3)) % n
}

/// An ORIPA `.cp` of two diagonals and `lines` overlapping pieces of one horizontal line
/// (80,000 of them: every pair was compared, 27 s).
pub fn collinear_pile_cp(lines: u64) -> String {
    let mut cp = String::from("1 0 0 100 100\n2 0 100 100 0\n");
    for k in 0..lines {
        let (a, b) = (scrambled(k, 0, 10_000), scrambled(k, 1, 10_000));
        cp.push_str(&format!(
            "2 {} 50 {} 50\n",
            a as f64 / 100.0,
            b as f64 / 100.0
        ));
    }
    cp
}

/// An SVG of `lines` long red lines across a 200 mm square, crossing each other about
/// `lines`² / 9 times (3,000 of them: 21 s and 600 MB).
pub fn crossing_lines_svg(lines: u64) -> String {
    let mut svg =
        String::from("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"200\">\n");
    for k in 0..lines {
        let c = |m: u64| scrambled(k, m, 20_000) as f64 / 100.0;
        svg.push_str(&format!(
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"red\"/>\n",
            c(0),
            c(1),
            c(2),
            c(3)
        ));
    }
    svg.push_str("</svg>\n");
    svg
}
