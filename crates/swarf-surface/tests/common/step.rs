//! A STEP file written entity by entity, for the STEP tests.

use swarf_surface::io::step;
use swarf_surface::CompoundSurface;

/// A STEP file written entity by entity (the tests add their own builders in `impl Step`
/// blocks of their own).
#[derive(Default)]
pub struct Step {
    pub lines: Vec<String>,
}

impl Step {
    /// Adds `body` (`PLANE('',#3)`) as the next instance; its number.
    pub fn add(&mut self, body: impl AsRef<str>) -> u64 {
        self.lines.push(body.as_ref().to_string());
        self.lines.len() as u64
    }

    /// The file.
    pub fn text(&self) -> String {
        let mut t = String::from(
            "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n",
        );
        for (k, l) in self.lines.iter().enumerate() {
            t.push_str(&format!("#{}={};\n", k + 1, l));
        }
        t.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
        t
    }

    /// The file read (a panic with the text when it does not read).
    pub fn parse(&self) -> CompoundSurface {
        step::parse(&self.text()).unwrap_or_else(|e| panic!("{e}\n{}", self.text()))
    }

    /// A unit context: millimetres, or inches when `inch`.
    pub fn context(&mut self, inch: bool) -> u64 {
        let mm = self.add("(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.))");
        let unit = if inch {
            let m = self.add(format!(
                "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#{mm})"
            ));
            let d = self.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
            self.add(format!(
                "(CONVERSION_BASED_UNIT('INCH',#{m}) LENGTH_UNIT() NAMED_UNIT(#{d}))"
            ))
        } else {
            mm
        };
        self.add(format!(
            "(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#{unit})) \
             REPRESENTATION_CONTEXT('',''))"
        ))
    }

    /// A `CARTESIAN_POINT`.
    pub fn point(&mut self, p: [f64; 3]) -> u64 {
        self.add(format!(
            "CARTESIAN_POINT('',({:?},{:?},{:?}))",
            p[0], p[1], p[2]
        ))
    }

    /// An `AXIS2_PLACEMENT_3D` at `o` with axis `z` and reference direction `x`.
    pub fn axis(&mut self, o: [f64; 3], z: [f64; 3], x: [f64; 3]) -> u64 {
        let o = self.point(o);
        let z = self.add(format!("DIRECTION('',({:?},{:?},{:?}))", z[0], z[1], z[2]));
        let x = self.add(format!("DIRECTION('',({:?},{:?},{:?}))", x[0], x[1], x[2]));
        self.add(format!("AXIS2_PLACEMENT_3D('',#{o},#{z},#{x})"))
    }
}
