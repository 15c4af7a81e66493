//! The machined part as a mesh: closed, outward, and the same solid as the dexels.

use swarf_geom::math::Vec3;
use swarf_stock::{ToolShape, TriDexel};
use swarf_tool::Cutter;

#[test]
fn slotted_block_meshes_closed_with_the_dexel_volume_and_crisp_walls() {
    let h = 0.25;
    let mut stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 20.0, 10.0), h).unwrap();
    let tool = ToolShape::new(&Cutter::flat(6.0).unwrap());
    // A through slot along X, 4 mm deep, and a ball pocket.
    stock.cut_linear(
        &tool,
        Vec3::new(-5.0, 10.0, 6.0),
        Vec3::new(45.0, 10.0, 6.0),
        Vec3::Z,
    );
    let ball = ToolShape::new(&Cutter::ball(8.0).unwrap());
    stock.cut_linear(
        &ball,
        Vec3::new(20.0, 4.0, 7.0),
        Vec3::new(20.0, 4.0, 7.0),
        Vec3::Z,
    );
    let (mesh, stats) = stock.to_mesh(&Default::default());
    assert!(mesh.is_closed(), "{:?}", mesh.edge_report());
    let v_mesh = mesh.volume();
    let v_dexel = stock.volume();
    assert!(
        (v_mesh - v_dexel).abs() / v_dexel < 2e-3,
        "{v_mesh} vs {v_dexel}"
    );
    assert_eq!(stats.fallback_crossings, 0, "{stats:?}");
    // The slot walls are planes y = 7 and y = 13: every vertex near them lies on them.
    let on_wall = mesh.vertices.iter().filter(|p| {
        p.z > 6.5
            && p.z < 9.5
            && p.x > 30.0
            && ((p.y - 7.0).abs() < 0.2 || (p.y - 13.0).abs() < 0.2)
    });
    let mut n = 0;
    for p in on_wall {
        n += 1;
        let d = (p.y - 7.0).abs().min((p.y - 13.0).abs());
        assert!(d < 1e-9, "wall vertex {p} is {d} mm off its wall");
    }
    assert!(n > 50, "{n} wall vertices");
}
