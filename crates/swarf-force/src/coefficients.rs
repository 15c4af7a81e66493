//! Cutting coefficients: given by a material file, built in, or predicted from an orthogonal
//! cutting database through the oblique transformation.
//!
//! A [`Material`] yields the six coefficients of the mechanistic model at a location
//! ([`Material::coefficients`]): a fixed set ([`CoefficientSource::Fixed`], from a TOML file or
//! a built-in table) or a prediction ([`CoefficientSource::Oblique`]) that depends on the tool's
//! normal rake and helix and on the mean uncut chip thickness, because the chip ratio of the
//! orthogonal database does.
//!
//! # The oblique transformation (Budak, Altintas & Armarego 1996)
//! From the orthogonal database at normal rake `αₙ` and chip thickness `h`: shear stress `τₛ`,
//! friction angle `βₙ`, chip ratio `r_c` and shear angle `φₙ = atan(r_c·cos αₙ / (1 − r_c·sin
//! αₙ))`; with helix `i` and chip flow angle `η = i` (Stabler's rule):
//!
//! ```text
//! k   = sqrt(cos²(φₙ + βₙ − αₙ) + tan²η·sin²βₙ)
//! Ktc = τₛ/sin φₙ · (cos(βₙ − αₙ) + tan i·tan η·sin βₙ) / k
//! Krc = τₛ/(sin φₙ·cos i) · sin(βₙ − αₙ) / k
//! Kac = τₛ/sin φₙ · (cos(βₙ − αₙ)·tan i − tan η·sin βₙ) / k
//! ```

use serde::{Deserialize, Serialize};

use crate::ForceError;

/// The six coefficients of the mechanistic model: shear (`ktc`, `krc`, `kac`, N/mm², per unit
/// chip area) and edge (`kte`, `kre`, `kae`, N/mm, per unit chip width).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Coefficients {
    /// Tangential shear coefficient, N/mm².
    pub ktc: f64,
    /// Radial shear coefficient, N/mm².
    pub krc: f64,
    /// Axial shear coefficient, N/mm².
    pub kac: f64,
    /// Tangential edge coefficient, N/mm.
    pub kte: f64,
    /// Radial edge coefficient, N/mm.
    pub kre: f64,
    /// Axial edge coefficient, N/mm.
    pub kae: f64,
}

impl Coefficients {
    /// The six in model order `[ktc, krc, kac, kte, kre, kae]`.
    pub fn as_array(&self) -> [f64; 6] {
        [self.ktc, self.krc, self.kac, self.kte, self.kre, self.kae]
    }
}

/// An orthogonal cutting database: the material's shear stress, friction angle and chip ratio
/// as functions of the normal rake `αₙ` (degrees) and chip thickness `h` (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OrthogonalDatabase {
    /// Shear stress τₛ, N/mm² (MPa).
    pub shear_stress_mpa: f64,
    /// Friction angle `βₙ = b0 + b1·αₙ`, degrees: `[b0, b1]`.
    pub friction_deg: [f64; 2],
    /// Chip ratio `r_c = C0·h^C1`, `C0 = c00 + c01·αₙ`, `C1 = c10 + c11·αₙ`:
    /// `[c00, c01, c10, c11]`.
    pub chip_ratio: [f64; 4],
}

impl OrthogonalDatabase {
    /// The shear coefficients (`ktc`, `krc`, `kac`, N/mm²) for normal rake `rake_deg`, helix
    /// `helix_deg` and chip thickness `h_mm`.
    pub fn shear_coefficients(&self, rake_deg: f64, helix_deg: f64, h_mm: f64) -> [f64; 3] {
        let an = rake_deg.to_radians();
        let bn = (self.friction_deg[0] + self.friction_deg[1] * rake_deg).to_radians();
        let [c00, c01, c10, c11] = self.chip_ratio;
        let rc = (c00 + c01 * rake_deg) * h_mm.max(1e-6).powf(c10 + c11 * rake_deg);
        let phin = (rc * an.cos() / (1.0 - rc * an.sin())).atan();
        let i = helix_deg.to_radians();
        let eta = i;
        let k = ((phin + bn - an).cos().powi(2) + (eta.tan() * bn.sin()).powi(2)).sqrt();
        let tau = self.shear_stress_mpa;
        let ktc = tau / phin.sin() * ((bn - an).cos() + i.tan() * eta.tan() * bn.sin()) / k;
        let krc = tau / (phin.sin() * i.cos()) * (bn - an).sin() / k;
        let kac = tau / phin.sin() * ((bn - an).cos() * i.tan() - eta.tan() * bn.sin()) / k;
        [ktc, krc, kac]
    }
}

/// Where a material's coefficients come from.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CoefficientSource {
    /// One fixed set.
    Fixed(Coefficients),
    /// Shear coefficients predicted from an orthogonal database per location (tool rake and
    /// helix, mean chip thickness); edge coefficients fixed.
    Oblique {
        /// The orthogonal database.
        database: OrthogonalDatabase,
        /// Edge coefficients `[kte, kre, kae]`, N/mm.
        edge: [f64; 3],
    },
}

/// A work material: a name, its coefficients and where they come from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Material {
    /// Name (`ti6al4v`, or a material file's `name`).
    pub name: String,
    /// The coefficients.
    pub coefficients: CoefficientSource,
    /// Citation or note on the values.
    pub source: String,
}

impl Material {
    /// The coefficients at a location cut by a tool of normal rake `rake_deg` (needed only by
    /// a prediction) and helix `helix_deg`, with mean uncut chip thickness `h_mean_mm`.
    ///
    /// # Errors
    /// A prediction without a rake angle.
    pub fn coefficients(
        &self,
        rake_deg: Option<f64>,
        helix_deg: f64,
        h_mean_mm: f64,
    ) -> Result<Coefficients, ForceError> {
        match &self.coefficients {
            CoefficientSource::Fixed(c) => Ok(*c),
            CoefficientSource::Oblique { database, edge } => {
                let rake = rake_deg.ok_or_else(|| ForceError::NoRake {
                    material: self.name.clone(),
                })?;
                let [ktc, krc, kac] = database.shear_coefficients(rake, helix_deg, h_mean_mm);
                Ok(Coefficients {
                    ktc,
                    krc,
                    kac,
                    kte: edge[0],
                    kre: edge[1],
                    kae: edge[2],
                })
            }
        }
    }

    /// True when the coefficients do not depend on the chip thickness.
    pub fn is_fixed(&self) -> bool {
        matches!(self.coefficients, CoefficientSource::Fixed(_))
    }
}

/// The Ti6Al4V orthogonal database of Budak, Altintas & Armarego (1996).
pub const TI6AL4V: OrthogonalDatabase = OrthogonalDatabase {
    shear_stress_mpa: 613.0,
    friction_deg: [19.1, 0.29],
    chip_ratio: [1.755, -0.028, 0.331, -0.0082],
};

/// The built-in materials, each naming its source.
pub fn builtin_materials() -> Vec<Material> {
    vec![Material {
        name: "ti6al4v".into(),
        coefficients: CoefficientSource::Oblique {
            database: TI6AL4V,
            edge: [0.0, 0.0, 0.0],
        },
        source: "E. Budak, Y. Altintas, E. J. A. Armarego, \"Prediction of milling force \
                 coefficients from orthogonal cutting data\", ASME J. Manufacturing Science and \
                 Engineering 118(2), 1996: orthogonal database (tau_s = 613 MPa, beta_n = 19.1 + \
                 0.29 alpha_n, r_c = (1.755 - 0.028 alpha_n) h^(0.331 - 0.0082 alpha_n)) through \
                 the oblique transformation with eta = i; shear coefficients only (edge \
                 coefficients 0: give measured ones in a --coefficients file)"
            .into(),
    }]
}

/// The built-in material called `name` (case-insensitive).
///
/// # Errors
/// An unknown name, listing the known ones.
pub fn builtin_material(name: &str) -> Result<Material, ForceError> {
    let all = builtin_materials();
    let known = all
        .iter()
        .map(|m| m.name.clone())
        .collect::<Vec<_>>()
        .join(", ");
    all.into_iter()
        .find(|m| m.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| ForceError::UnknownMaterial {
            name: name.to_string(),
            known,
        })
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    name: String,
    ktc: f64,
    krc: f64,
    kac: f64,
    kte: f64,
    kre: f64,
    kae: f64,
    #[serde(default)]
    source: Option<String>,
}

/// Reads a material file (TOML: `name`, `ktc`, `krc`, `kac` in N/mm², `kte`, `kre`, `kae` in
/// N/mm, optional `source`); `file` names it in errors.
///
/// # Errors
/// Syntax errors, missing or unknown keys and non-finite values, at their line and column.
pub fn parse_material(text: &str, file: &str) -> Result<Material, ForceError> {
    let m: MaterialFile = toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
        ForceError::MaterialFile {
            file: file.to_string(),
            line,
            column,
            problem: e.message().trim().to_string(),
            expected: "a material file is TOML with name, ktc, krc, kac (N/mm²), kte, kre, kae \
                       (N/mm) and an optional source"
                .into(),
        }
    })?;
    let c = Coefficients {
        ktc: m.ktc,
        krc: m.krc,
        kac: m.kac,
        kte: m.kte,
        kre: m.kre,
        kae: m.kae,
    };
    for (key, v) in ["ktc", "krc", "kac", "kte", "kre", "kae"]
        .iter()
        .zip(c.as_array())
    {
        // The tangential and radial coefficients, shear and edge, are forces the chip and the
        // edge's rubbing push against the tool along −t and −r: never negative (a negative one
        // is a failed fit, and would make power negative or pull the tool into the wall). The
        // axial ones may be negative: their sign follows the helix's hand and the chip flow,
        // and the oblique prediction itself gives Kac < 0 where friction outweighs the helix.
        let expected = if !v.is_finite() {
            "the coefficients are finite numbers"
        } else if v < 0.0 && !key.starts_with("ka") {
            "the tangential and radial coefficients (ktc, krc, kte, kre) are at least 0; only the axial ones (kac, kae) may be negative"
        } else {
            continue;
        };
        let (line, column) = line_col(text, key_offset(text, key));
        return Err(ForceError::MaterialFile {
            file: file.to_string(),
            line,
            column,
            problem: format!("{key} = {v}"),
            expected: expected.into(),
        });
    }
    Ok(Material {
        name: m.name,
        coefficients: CoefficientSource::Fixed(c),
        source: m
            .source
            .unwrap_or_else(|| format!("material file {file} (no source given)")),
    })
}

use swarf_geom::text::line_col;

/// Byte offset of the line that sets `key` (the key at the start of a line, before `=`), or 0.
fn key_offset(text: &str, key: &str) -> usize {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if t.strip_prefix(key)
            .is_some_and(|rest| rest.trim_start().starts_with('='))
        {
            return at + (line.len() - t.len());
        }
        at += line.len();
    }
    0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn oblique_prediction_reduces_to_merchant_at_zero_helix() {
        // i = η = 0: Ktc = τ cos(β−α)/(sin φ cos(φ+β−α)), Krc = τ sin(β−α)/(sin φ cos(φ+β−α)),
        // Kac = 0 (the orthogonal, Merchant, result).
        let (rake, h) = (10.0f64, 0.05f64);
        let [ktc, krc, kac] = TI6AL4V.shear_coefficients(rake, 0.0, h);
        let an = rake.to_radians();
        let bn = (19.1 + 0.29 * rake).to_radians();
        let rc = (1.755 - 0.028 * rake) * h.powf(0.331 - 0.0082 * rake);
        let phi = (rc * an.cos() / (1.0 - rc * an.sin())).atan();
        let d = phi.sin() * (phi + bn - an).cos();
        assert!((ktc - 613.0 * (bn - an).cos() / d).abs() < 1e-9);
        assert!((krc - 613.0 * (bn - an).sin() / d).abs() < 1e-9);
        assert!(kac.abs() < 1e-9);
        // A positive helix gives a positive axial coefficient here and raises Ktc slightly.
        let [ktc30, _, kac30] = TI6AL4V.shear_coefficients(rake, 30.0, h);
        assert!(kac30 > 0.0 && ktc30 > ktc);
    }

    #[test]
    fn material_files_read_and_fail_at_their_line() {
        let m = parse_material(
            "name = \"Al7075\"\nktc = 796\nkrc = 168.8\nkac = 222\nkte = 27.7\nkre = 30.8\nkae = 1.8\n",
            "al.toml",
        )
        .unwrap();
        assert_eq!(m.name, "Al7075");
        assert!(m.source.contains("al.toml"));
        let e = parse_material("name = \"x\"\nktc = 796\nkrc = oops\n", "bad.toml").unwrap_err();
        let s = e.to_string();
        assert!(s.starts_with("bad.toml:3:"), "{s}");
        let e = parse_material("name = \"x\"\nktc = 1\n", "short.toml").unwrap_err();
        assert!(e.to_string().contains("krc"), "{e}");
        assert!(builtin_material("Ti6Al4V").is_ok());
        // NaN and a negative tangential or radial coefficient are refused at their key.
        let e = parse_material(
            "name=\"x\"\nktc=nan\nkrc=1\nkac=1\nkte=0\nkre=0\nkae=0\n",
            "nan.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("nan.toml:2:1: ktc = NaN"), "{e}");
        assert!(e.contains("finite"), "{e}");
        let base = [
            "ktc = 796",
            "krc = 168.8",
            "kac = 222",
            "kte = 27.7",
            "kre = 30.8",
            "kae = 1.8",
        ];
        for (i, key) in ["ktc", "krc", "kac", "kte", "kre", "kae"]
            .iter()
            .enumerate()
        {
            let mut lines = base.map(String::from);
            lines[i] = format!("{key} = -5");
            // The name mentions every key first: the error still points at the key's line.
            let text = format!("name = \"ktc krc kac kte kre kae\"\n{}\n", lines.join("\n"));
            let got = parse_material(&text, "neg.toml");
            if key.starts_with("ka") {
                let m = got.unwrap_or_else(|e| panic!("{key}: {e}"));
                assert!(
                    matches!(m.coefficients, CoefficientSource::Fixed(c) if c.as_array()[i] == -5.0)
                );
            } else {
                let e = got.unwrap_err().to_string();
                assert!(
                    e.starts_with(&format!("neg.toml:{}:1: {key} = -5 (", i + 2)),
                    "{key}: {e}"
                );
                assert!(e.contains("at least 0"), "{e}");
            }
        }
        let e = builtin_material("steel").unwrap_err().to_string();
        assert!(e.contains("ti6al4v"), "{e}");
    }
}
