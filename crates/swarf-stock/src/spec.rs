//! Stock spec strings, as the command line takes them: `box:X0,Y0,Z0,X1,Y1,Z1`,
//! `cyl:CX,CY,Z0,R,H` (axis +Z, base at Z0) or the path of a closed STL mesh. Millimetres.

use std::path::PathBuf;

use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

use crate::{MeshOptions, StockError, TriDexel};

/// An initial workpiece, before it is sampled into a [`TriDexel`].
#[derive(Clone, Debug, PartialEq)]
pub enum StockSpec {
    /// An axis-aligned block between two corners.
    Box {
        /// Lower corner, mm.
        min: Vec3,
        /// Upper corner, mm.
        max: Vec3,
    },
    /// A round bar standing on the XY plane: centre, base height, radius, height.
    Cylinder {
        /// Axis position X, mm.
        cx: f64,
        /// Axis position Y, mm.
        cy: f64,
        /// Base height, mm.
        z0: f64,
        /// Radius, mm.
        r: f64,
        /// Height, mm.
        height: f64,
    },
    /// A closed triangle mesh (binary or ASCII STL).
    Mesh(PathBuf),
}

impl StockSpec {
    /// Reads a spec string. Anything that is neither `box:` nor `cyl:` is taken as a file path.
    ///
    /// ```
    /// use swarf_stock::spec::StockSpec;
    /// let s = StockSpec::parse("box:0,0,-20,100,80,0").unwrap();
    /// assert_eq!(s.bounds().unwrap().max.z, 0.0);
    /// assert!(StockSpec::parse("box:0,0,1").is_err());
    /// ```
    ///
    /// # Errors
    /// [`StockError::Spec`] with the column, what was found and what was expected, or
    /// [`StockError::BadDimensions`] for an empty or inverted shape.
    pub fn parse(spec: &str) -> Result<Self, StockError> {
        let lower = spec.to_ascii_lowercase();
        let (kind, count, expected) = if lower.starts_with("box:") {
            ("box", 6, "six numbers X0,Y0,Z0,X1,Y1,Z1")
        } else if lower.starts_with("cyl:") {
            ("cyl", 5, "five numbers CX,CY,Z0,R,H")
        } else if !std::path::Path::new(spec).exists() && spec.contains([',', ':']) {
            // Neither a file nor a shape: a misspelt shape (`cylinder:…`, `box 0,0,…`) is more
            // likely than a file of that name.
            return Err(StockError::Spec {
                column: 1,
                found: format!("`{spec}`, which is no file"),
                expected: "`box:X0,Y0,Z0,X1,Y1,Z1`, `cyl:CX,CY,Z0,R,H` or a closed STL file".into(),
            });
        } else {
            return Ok(StockSpec::Mesh(PathBuf::from(spec)));
        };
        let body = &spec[4..];
        let mut v = Vec::with_capacity(count);
        let mut column = 5;
        for field in body.split(',') {
            let t = field.trim();
            let x: f64 = t
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| StockError::Spec {
                    column,
                    found: if t.is_empty() {
                        "nothing".into()
                    } else {
                        format!("`{t}`")
                    },
                    expected: "a finite number (mm)".into(),
                })?;
            v.push(x);
            column += field.chars().count() + 1;
        }
        if v.len() != count {
            return Err(StockError::Spec {
                column: 5,
                found: format!("{} number(s)", v.len()),
                expected: expected.into(),
            });
        }
        if kind == "box" {
            let (a, b) = (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]));
            let (min, max) = (a.min(b), a.max(b));
            if (max - min).min_element() <= 0.0 {
                return Err(StockError::BadDimensions(format!(
                    "box {spec} has no volume"
                )));
            }
            Ok(StockSpec::Box { min, max })
        } else {
            if v[3] <= 0.0 || v[4] <= 0.0 {
                return Err(StockError::BadDimensions(format!(
                    "cylinder {spec}: radius and height must be positive"
                )));
            }
            Ok(StockSpec::Cylinder {
                cx: v[0],
                cy: v[1],
                z0: v[2],
                r: v[3],
                height: v[4],
            })
        }
    }

    /// The bounds of a box or cylinder (a mesh's are known once it is read).
    pub fn bounds(&self) -> Option<Aabb> {
        match *self {
            StockSpec::Box { min, max } => Some(Aabb::new(min, max)),
            StockSpec::Cylinder {
                cx,
                cy,
                z0,
                r,
                height,
            } => Some(Aabb::new(
                Vec3::new(cx - r, cy - r, z0),
                Vec3::new(cx + r, cy + r, z0 + height),
            )),
            StockSpec::Mesh(_) => None,
        }
    }

    /// Samples the stock at resolution `h` (mm).
    ///
    /// # Errors
    /// The mesh file cannot be read or is not closed (unless `mesh.allow_open`), or the grid is
    /// too fine for the stock.
    pub fn build(&self, h: f64, mesh: MeshOptions) -> Result<TriDexel, StockError> {
        match self {
            StockSpec::Box { min, max } => TriDexel::from_box(*min, *max, h),
            StockSpec::Cylinder {
                cx,
                cy,
                z0,
                r,
                height,
            } => TriDexel::from_cylinder(*cx, *cy, *z0, *r, *height, h),
            StockSpec::Mesh(path) => {
                let bytes = std::fs::read(path).map_err(|e| StockError::Io {
                    file: path.display().to_string(),
                    message: e.to_string(),
                })?;
                // Every error of the mesh's stock is about the file (its syntax, closedness,
                // extent beyond the machine range, size for the resolution): it names it.
                TriDexel::from_stl_bytes(&bytes, h, mesh).map_err(|e| StockError::Io {
                    file: path.display().to_string(),
                    message: e.to_string(),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_corners_in_any_order() {
        let s = StockSpec::parse("box:10,0,0,0,5,-3").unwrap();
        assert_eq!(
            s,
            StockSpec::Box {
                min: Vec3::new(0.0, 0.0, -3.0),
                max: Vec3::new(10.0, 5.0, 0.0)
            }
        );
    }

    #[test]
    fn cylinder_bounds() {
        let s = StockSpec::parse("cyl:1,2,-10,5,10").unwrap();
        let b = s.bounds().unwrap();
        assert_eq!(
            (b.min, b.max),
            (Vec3::new(-4.0, -3.0, -10.0), Vec3::new(6.0, 7.0, 0.0))
        );
    }

    #[test]
    fn errors_name_the_column() {
        match StockSpec::parse("box:0,0,x,1,1,1") {
            Err(StockError::Spec { column, found, .. }) => {
                assert_eq!(column, 9);
                assert_eq!(found, "`x`");
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            StockSpec::parse("cyl:0,0,0,5"),
            Err(StockError::Spec { .. })
        ));
        assert!(matches!(
            StockSpec::parse("cyl:0,0,0,-5,3"),
            Err(StockError::BadDimensions(_))
        ));
        assert!(matches!(
            StockSpec::parse("box:0,0,0,1,1,0"),
            Err(StockError::BadDimensions(_))
        ));
        assert!(matches!(
            StockSpec::parse("box:0,0,0,1,1,nan"),
            Err(StockError::Spec { .. })
        ));
        // A misspelt shape that is no file names the shapes (it was "No such file").
        for spec in ["cylinder:0,0,0,5,10", "box 0,0,0,10,10,10"] {
            match StockSpec::parse(spec) {
                Err(StockError::Spec {
                    column, expected, ..
                }) => {
                    assert_eq!(column, 1);
                    assert!(expected.contains("box:") && expected.contains("cyl:"));
                }
                other => panic!("{spec}: {other:?}"),
            }
        }
        // A plain file name is still a mesh stock (read, and refused, later).
        assert!(matches!(
            StockSpec::parse("part.stl"),
            Ok(StockSpec::Mesh(_))
        ));
    }

    #[test]
    fn mesh_errors_name_the_file_once() {
        let dir = swarf_testdata::scratch_dir("stock-spec");
        std::fs::create_dir_all(&dir).unwrap();
        // A box from (0, 0, 0) to (x1, 20, 10) as binary STL.
        let stl = |x1: f64| {
            let mut b = Vec::new();
            let m = swarf_io::TriMesh::cuboid(Vec3::ZERO, Vec3::new(x1, 20.0, 10.0));
            swarf_io::write_stl_to(&mut b, &m).unwrap();
            b
        };
        let build = |name: &str, bytes: &[u8]| {
            let path = dir.join(name);
            std::fs::write(&path, bytes).unwrap();
            let spec = StockSpec::parse(path.to_str().unwrap()).unwrap();
            (
                path.display().to_string(),
                spec.build(1.0, MeshOptions::default()),
            )
        };
        let (_, ok) = build("box.stl", &stl(20.0));
        assert!((ok.unwrap().volume() - 4000.0).abs() < 1e-6);
        // One triangle left out.
        let mut open = stl(20.0)[..84 + 50 * 11].to_vec();
        open[80..84].copy_from_slice(&11u32.to_le_bytes());
        let cases = [
            (
                "syntax.stl",
                b"solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zz\n".to_vec(),
                "`zz`",
            ),
            ("huge.stl", stl(2e6), "machine range"),
            ("open.stl", open, "not closed"),
        ];
        for (name, bytes, what) in cases {
            let (file, e) = build(name, &bytes);
            let e = e.unwrap_err().to_string();
            assert!(e.starts_with(&format!("{file}: ")), "{e}");
            assert!(e.contains(what) && e.matches(name).count() == 1, "{e}");
            assert!(!e.contains("<stl>"), "{e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_mesh_is_an_io_error() {
        let s = StockSpec::parse("/nonexistent/part.stl").unwrap();
        assert!(matches!(
            s.build(1.0, MeshOptions::default()),
            Err(StockError::Io { .. })
        ));
    }
}
