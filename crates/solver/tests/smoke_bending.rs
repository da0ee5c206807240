use axijoint_mesh::prepare;
use axijoint_solver::assembly::JointModel;
use axijoint_solver::elements::edge_load;
use axijoint_solver::linear::Model;
use axijoint_solver::material::Elastic;
use std::path::Path;

#[test]
fn smoke_pure_bending() {
    let geo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/cylinder.geo");
    let (e, nu, s) = (2.0e4, 0.17, 3.0);
    for (order, quads) in [(2.0, 1.0), (2.0, 0.0)] {
        let params = vec![("order".to_string(), order), ("quads".to_string(), quads), ("size".into(), 0.3)];
        let (mesh, _) = prepare(&geo, &params, &[], None).unwrap();
        let n = mesh.nodes.len();
        let mut fixed = vec![false; 3 * n];
        for ed in &mesh.curve("bottom").unwrap().edges { for &k in &ed.nodes { fixed[3 * k + 1] = true; } }
        for &k in &mesh.point("origin").unwrap().nodes { fixed[3 * k] = true; }
        let mut f = vec![0.0; 3 * n];
        for ed in &mesh.curve("top").unwrap().edges {
            let coords: Vec<[f64; 2]> = ed.nodes.iter().map(|&k| mesh.nodes[k]).collect();
            let mut fe = vec![0.0; 3 * ed.nodes.len()];
            edge_load(ed.kind, &coords, 1, &|r, _z| [0.0, s * r, 0.0], &mut fe);
            for (i, &k) in ed.nodes.iter().enumerate() { for c in 0..3 { f[3 * k + c] += fe[3 * i + c]; } }
        }
        let nodes = mesh.nodes.clone();
        let model = Model::new(mesh, vec![Elastic::new(e, nu).unwrap()], Vec::<JointModel>::new(), fixed).unwrap();
        let fac = model.factorize(1).unwrap();
        let u = &model.solve(&fac, &[&f])[0];
        let mut err: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for (k, p) in nodes.iter().enumerate() {
            let (r, z) = (p[0], p[1]);
            let ex = [-s / (2.0 * e) * (z * z + nu * r * r), s * r * z / e, s / (2.0 * e) * (z * z - nu * r * r)];
            for c in 0..3 { err = err.max((u[3 * k + c] - ex[c]).abs()); scale = scale.max(ex[c].abs()); }
        }
        println!("order {order} quads {quads}: max err {:.3e} rel {:.3e}", err, err / scale);
        assert!(err / scale < 1e-8);
    }
}
