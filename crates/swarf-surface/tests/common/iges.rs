//! IGES files built in code, for the IGES reader's tests.

/// An IGES file built in code: entities in order (DE 1, 3, 5, …), each its type, its
/// parameters (without the terminating `;`) and its transformation's DE (0: none).
#[derive(Default)]
pub struct Iges {
    /// The entities: type, parameters with their `;`, transformation DE.
    pub entities: Vec<(u32, String, usize)>,
}

impl Iges {
    /// Adds an entity; returns its DE.
    pub fn add(&mut self, kind: u32, params: &str) -> usize {
        self.add_moved(kind, params, 0)
    }

    /// Adds an entity moved by the 124 at `transform`; returns its DE.
    pub fn add_moved(&mut self, kind: u32, params: &str, transform: usize) -> usize {
        self.entities
            .push((kind, format!("{kind},{params};"), transform));
        2 * self.entities.len() - 1
    }

    /// The file, in mm (`units = "2,2HMM"`) or other units (flag, name).
    pub fn text(&self, units: &str) -> String {
        let g = format!(
            "1H,,1H;,4Hswrf,8Htest.igs,4Hswrf,4Hswrf,32,308,15,308,15,4Hswrf,1.,{units},1,0.01,15H20240101.000000,1e-6,100.,4Hswrf,,11,0,15H20240101.000000;"
        );
        let mut out = vec![format!(
            "{:<72}S{:07}",
            "built by the swarf-surface tests", 1
        )];
        let gb = g.as_bytes();
        let glines: Vec<&[u8]> = gb.chunks(72).collect();
        for (k, c) in glines.iter().enumerate() {
            out.push(format!(
                "{:<72}G{:07}",
                std::str::from_utf8(c).unwrap(),
                k + 1
            ));
        }
        let mut p_lines = Vec::new();
        let mut d_lines = Vec::new();
        for (k, (kind, params, transform)) in self.entities.iter().enumerate() {
            let de = 2 * k + 1;
            let start = p_lines.len() + 1;
            let mut cur = String::new();
            let mut recs = Vec::new();
            for tok in params.split_inclusive(',') {
                if cur.len() + tok.len() > 64 {
                    recs.push(std::mem::take(&mut cur));
                }
                cur.push_str(tok);
            }
            recs.push(cur);
            for r in &recs {
                p_lines.push(format!("{r:<64}{de:>8}P{:07}", p_lines.len() + 1));
            }
            d_lines.push(format!(
                "{kind:>8}{start:>8}{:>8}{:>8}{:>8}{:>8}{transform:>8}{:>8}{:>8}D{:07}",
                0, 0, 0, 0, 0, "00000000", de
            ));
            d_lines.push(format!(
                "{kind:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:07}",
                0,
                0,
                recs.len(),
                0,
                "",
                "",
                "",
                0,
                de + 1
            ));
        }
        out.extend(d_lines.iter().cloned());
        out.extend(p_lines.iter().cloned());
        out.push(format!(
            "{:<72}T{:07}",
            format!(
                "S{:07}G{:07}D{:07}P{:07}",
                1,
                glines.len(),
                d_lines.len(),
                p_lines.len()
            ),
            1
        ));
        out.join("\n") + "\n"
    }
}

/// A 10 mm square plate over `[0, 1]²` (u along x, v along y).
pub const PLATE: &str = "1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,0.,0.,0.,10.,0.,0.,0.,10.,0.,10.,10.,0.,0.,1.,0.,1.";

/// A closed polygon of 110 lines as a 102; returns the 102's DE.
pub fn polygon(f: &mut Iges, pts: &[[f64; 2]]) -> usize {
    let members: Vec<String> = (0..pts.len())
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            f.add(110, &format!("{},{},0.,{},{},0.", a[0], a[1], b[0], b[1]))
                .to_string()
        })
        .collect();
    f.add(102, &format!("{},{}", members.len(), members.join(",")))
}

/// A full circle as a rational quadratic 126 (9 control points, 4 spans).
pub fn circle126(f: &mut Iges, c: [f64; 2], r: f64) -> usize {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let corners = [
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [-1.0, 1.0],
        [-1.0, 0.0],
        [-1.0, -1.0],
        [0.0, -1.0],
        [1.0, -1.0],
        [1.0, 0.0],
    ];
    let knots = "0,0,0,1,1,2,2,3,3,4,4,4";
    let weights: Vec<String> = (0..9)
        .map(|i| {
            if i % 2 == 1 {
                w.to_string()
            } else {
                "1".into()
            }
        })
        .collect();
    let points: Vec<String> = corners
        .iter()
        .map(|q| format!("{},{},0", c[0] + r * q[0], c[1] + r * q[1]))
        .collect();
    f.add(
        126,
        &format!(
            "8,2,1,1,0,0,{knots},{},{},0,4,0,0,1",
            weights.join(","),
            points.join(",")
        ),
    )
}

/// The plate with one hole whose 142 is built by `hole` (given the plate's DE; returns the
/// 142's DE).
pub fn plate_with(hole: impl FnOnce(&mut Iges, usize) -> usize) -> String {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let c = hole(&mut f, plate);
    f.add(144, &format!("{plate},0,1,0,{c}"));
    f.text("2,2HMM")
}
