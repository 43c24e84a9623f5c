//! CSG traced directly, checked against a brute-force point-membership oracle: random
//! trees of transformed solids, the spans of every solid primitive, normal orientation on
//! every face, per-leaf materials, and rendering through CSG solids.

use std::sync::atomic::AtomicBool;

use glam::{DVec3, Vec3};
use glint_core::desc::*;
use glint_core::math::{Ray, Transform};
use glint_core::render::render;
use glint_core::scene::{RenderScene, compile};
use glint_core::shape::{Shape, ShapeKind, Solid, Span};
use proptest::prelude::*;

/// A leaf solid in object space: which primitive, and its oracle.
#[derive(Clone, Copy, Debug)]
enum Leaf {
    Sphere,
    Cube,
    Cylinder,
    Cone,
    Torus,
    Plane,
    Quadric,
    Superellipsoid,
}

const LEAVES: [Leaf; 8] = [
    Leaf::Sphere,
    Leaf::Cube,
    Leaf::Cylinder,
    Leaf::Cone,
    Leaf::Torus,
    Leaf::Plane,
    Leaf::Quadric,
    Leaf::Superellipsoid,
];

/// Hyperboloid of one sheet x² − y² + z² − 0.25 ≤ 0, clipped to [−1, 1]³.
const HYPERBOLOID: [f32; 10] = [1.0, -1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.25];
const SUPER: (f32, f32) = (0.5, 1.5);
const TORUS_R: f32 = 0.35;

impl Leaf {
    fn desc(self, material: usize) -> NodeKind {
        let shape = |shape| NodeKind::Shape { shape, material };
        match self {
            Leaf::Sphere => shape(ShapeDesc::Sphere),
            Leaf::Cube => shape(ShapeDesc::Cube),
            Leaf::Cylinder => shape(ShapeDesc::Cylinder),
            Leaf::Cone => shape(ShapeDesc::Cone),
            Leaf::Torus => shape(ShapeDesc::Torus { minor_radius: TORUS_R }),
            Leaf::Plane => shape(ShapeDesc::Plane),
            Leaf::Quadric => NodeKind::Solid(SolidDesc::Quadric {
                coefficients: HYPERBOLOID,
                bounds: Some([Vec3::splat(-1.0), Vec3::ONE]),
                material,
            }),
            Leaf::Superellipsoid => NodeKind::Solid(SolidDesc::Superellipsoid { e1: SUPER.0, e2: SUPER.1, material }),
        }
    }

    /// Membership, written independently of the intersectors.
    fn inside(self, p: DVec3) -> bool {
        let r = TORUS_R as f64;
        match self {
            Leaf::Sphere => p.length_squared() < 1.0,
            Leaf::Cube => p.abs().max_element() < 1.0,
            Leaf::Cylinder => p.x * p.x + p.z * p.z < 1.0 && p.y.abs() < 1.0,
            Leaf::Cone => p.y.abs() < 1.0 && p.x * p.x + p.z * p.z < 0.25 * (1.0 - p.y).powi(2),
            Leaf::Torus => (p.length_squared() + 1.0 - r * r).powi(2) < 4.0 * (p.x * p.x + p.z * p.z),
            Leaf::Plane => p.y < 0.0,
            Leaf::Quadric => p.abs().max_element() < 1.0 && p.x * p.x - p.y * p.y + p.z * p.z < 0.25,
            Leaf::Superellipsoid => {
                let (e1, e2) = (SUPER.0 as f64, SUPER.1 as f64);
                let a = p.x.abs().powf(2.0 / e2) + p.z.abs().powf(2.0 / e2);
                a.powf(e2 / e1) + p.y.abs().powf(2.0 / e1) < 1.0
            }
        }
    }
}

/// A random CSG tree: leaves with a placement, operations over two or three children.
#[derive(Clone, Debug)]
enum Tree {
    Leaf { leaf: Leaf, material: usize, transform: Vec<TransformOp> },
    Op { op: SetOp, children: Vec<Tree>, transform: Vec<TransformOp> },
}

impl Tree {
    fn node(&self) -> NodeDesc {
        match self {
            Tree::Leaf { leaf, material, transform } => {
                NodeDesc { transform: transform.clone(), kind: leaf.desc(*material), origin: format!("{leaf:?}") }
            }
            Tree::Op { op, children, transform } => NodeDesc {
                transform: transform.clone(),
                kind: NodeKind::Solid(SolidDesc::Csg { op: *op, children: children.iter().map(Tree::node).collect() }),
                origin: format!("{op:?}"),
            },
        }
    }

    fn transform(&self) -> Transform {
        let ops = match self {
            Tree::Leaf { transform, .. } | Tree::Op { transform, .. } => transform,
        };
        ops.iter().fold(Transform::IDENTITY, |acc, op| {
            let t = match *op {
                TransformOp::Translate(v) => Transform::translate(v),
                TransformOp::Scale(s) => Transform::scale(s).expect("non-zero scale"),
                TransformOp::Rotate { axis, degrees } => Transform::rotate(axis, degrees).expect("axis"),
                TransformOp::Matrix(_) => unreachable!(),
            };
            acc.then(&t)
        })
    }

    /// Membership of a point given in the parent's space.
    fn inside(&self, p: DVec3) -> bool {
        let local = self.transform().object_from_world.as_dmat4().transform_point3(p);
        match self {
            Tree::Leaf { leaf, .. } => leaf.inside(local),
            Tree::Op { op, children, .. } => {
                let mut members = children.iter().map(|c| c.inside(local));
                let first = members.next().unwrap_or(false);
                match op {
                    SetOp::Union => members.fold(first, |a, b| a || b),
                    SetOp::Intersection => members.fold(first, |a, b| a && b),
                    SetOp::Difference => members.fold(first, |a, b| a && !b),
                }
            }
        }
    }

    /// How many leaves the tree has.
    fn leaves(&self) -> usize {
        match self {
            Tree::Leaf { .. } => 1,
            Tree::Op { children, .. } => children.iter().map(Tree::leaves).sum(),
        }
    }
}

fn placement() -> impl Strategy<Value = Vec<TransformOp>> {
    (
        (0.4f32..1.6, 0.4f32..1.6, 0.4f32..1.6),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        -180.0f32..180.0,
        (-0.8f32..0.8, -0.8f32..0.8, -0.8f32..0.8),
    )
        .prop_map(|(s, axis, degrees, t)| {
            let axis = Vec3::new(axis.0, axis.1, axis.2);
            let axis = if axis.length() > 0.1 { axis } else { Vec3::Y };
            vec![
                TransformOp::Scale(Vec3::new(s.0, s.1, s.2)),
                TransformOp::Rotate { axis, degrees },
                TransformOp::Translate(Vec3::new(t.0, t.1, t.2)),
            ]
        })
}

fn tree() -> impl Strategy<Value = Tree> {
    let leaf = (0..LEAVES.len(), 0usize..3, placement()).prop_map(|(i, material, transform)| Tree::Leaf {
        leaf: LEAVES[i],
        material,
        transform,
    });
    leaf.prop_recursive(3, 12, 3, |inner| {
        (
            prop::sample::select(vec![SetOp::Union, SetOp::Intersection, SetOp::Difference]),
            prop::collection::vec(inner, 2..=3),
            prop_oneof![Just(Vec::new()), placement()],
        )
            .prop_map(|(op, children, transform)| Tree::Op { op, children, transform })
    })
}

fn materials() -> Vec<MaterialDesc> {
    (0..3).map(|i| MaterialDesc { name: format!("m{i}"), ..Default::default() }).collect()
}

fn scene_of(objects: Vec<NodeDesc>) -> RenderScene {
    let desc = SceneDesc {
        settings: RenderSettings { width: 8, height: 8, ..Default::default() },
        materials: materials(),
        objects,
        ..Default::default()
    };
    compile(&desc).expect("compiles")
}

/// The CSG instance of a one-object scene (none when the solid is empty).
fn csg_of(scene: &RenderScene) -> Option<(glint_core::shape::CsgShape<'_>, Transform)> {
    let inst = scene.instances.first()?;
    assert_eq!(inst.shape.kind, ShapeKind::Csg);
    Some((scene.shape_tables.csg(inst.shape.index()), inst.transform))
}

fn random_ray(seed: (f32, f32, f32), target: (f32, f32, f32)) -> Ray {
    let from = Vec3::new(seed.0, seed.1, seed.2).normalize_or(Vec3::Z) * 5.0;
    let to = Vec3::new(target.0, target.1, target.2);
    Ray::new(from, (to - from) * 0.37)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(250))]

    /// Along random lines the combined spans say "inside" exactly where the tree's
    /// membership oracle does (away from surfaces, where rounding decides).
    #[test]
    fn csg_spans_match_point_membership(
        tree in tree(),
        rays in prop::collection::vec(((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0), (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)), 12),
    ) {
        prop_assume!(matches!(tree, Tree::Op { .. }), "a lone leaf is no CSG tree");
        let scene = scene_of(vec![tree.node()]);
        let Some((csg, xf)) = csg_of(&scene) else {
            // Compiled to nothing: the oracle must agree it is empty along the rays.
            for (seed, target) in rays {
                let ray = random_ray(seed, target);
                for k in 0..100 {
                    let p = ray.at(k as f32 * 0.1).as_dvec3();
                    prop_assert!(!tree.inside(p));
                }
            }
            return Ok(());
        };
        let mut spans: Vec<Span> = Vec::new();
        for (seed, target) in rays {
            let ray = random_ray(seed, target);
            spans.clear();
            csg.spans(&xf.ray_to_object(&ray), &mut spans);
            for pair in spans.windows(2) {
                prop_assert!(pair[0].exit.t < pair[1].enter.t);
            }
            for s in &spans {
                prop_assert!(s.enter.t < s.exit.t);
            }
            let eps = 1e-4;
            for k in 0..400 {
                let t = k as f32 * 0.0125 - 0.5;
                let near = |dt: f32| tree.inside(ray.at(t + dt).as_dvec3());
                let member = near(0.0);
                if member != near(-eps) || member != near(eps) {
                    continue; // at a surface
                }
                let in_spans = spans.iter().any(|s| s.enter.t < t && t < s.exit.t);
                prop_assert_eq!(in_spans, member, "t = {}, spans {:?}", t, spans);
            }
            // The nearest hit is a crossing of the oracle, with an outward normal.
            if let Some(hit) = scene.intersect(&ray, f32::INFINITY) {
                let before = tree.inside(ray.at(hit.t - 1e-3).as_dvec3());
                let after = tree.inside(ray.at(hit.t + 1e-3).as_dvec3());
                let n = hit.normal.as_dvec3();
                let p = hit.point.as_dvec3();
                let d = ray.dir.normalize().as_dvec3();
                // A grazing hit (far along an infinite half-space, say) flips membership
                // within the probe's ±1e-3 only by rounding: there orientation means nothing.
                if before != after && n.dot(d).abs() > 0.05 {
                    // Entering: the normal faces the ray; leaving: it goes along.
                    prop_assert_eq!(n.dot(d) < 0.0, after, "normal {:?} at t {}", n, hit.t);
                    prop_assert!(!tree.inside(p + n * 1e-3) || tree.inside(p - n * 1e-3));
                }
                prop_assert!((hit.material as usize) < 3);
            }
        }
        prop_assert!(tree.leaves() >= 2);
    }
}

/// Membership of each solid primitive's spans, along many lines from every side.
#[test]
fn every_solid_reports_the_spans_of_its_inside() {
    for leaf in LEAVES {
        let scene = scene_of(vec![NodeDesc { transform: vec![], kind: leaf.desc(0), origin: String::new() }]);
        let shape: Shape = scene.instances[0].shape;
        let mut state = 7u64;
        let mut random = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 33) as f64 / (1u64 << 31) as f64) as f32 * 2.0 - 1.0
        };
        let mut spans = Vec::new();
        for _ in 0..3000 {
            let ray = random_ray((random(), random(), random()), (random(), random(), random()));
            spans.clear();
            shape.spans_with(&scene.shape_tables, &ray, &mut spans);
            for k in 0..300 {
                let t = k as f32 * 0.02 - 1.0;
                let at = |dt: f32| leaf.inside(ray.at(t + dt).as_dvec3());
                if at(0.0) != at(1e-4) || at(0.0) != at(-1e-4) {
                    continue;
                }
                let in_spans = spans.iter().any(|s| s.enter.t < t && t < s.exit.t);
                assert_eq!(in_spans, at(0.0), "{leaf:?}: t = {t}, ray {ray:?}, spans {spans:?}");
            }
            // The nearest hit agrees with the first crossing of the spans.
            let near = shape.intersect_with(&scene.shape_tables, &ray, f32::INFINITY);
            let first = glint_core::shape::first_crossing(&spans, f32::INFINITY);
            match (near, first) {
                (Some(a), Some(b)) => assert!((a.t - b.t).abs() < 1e-4 * a.t.max(1.0), "{leaf:?}: {a:?} vs {b:?}"),
                (None, None) => {}
                // A tangent touch is a hit for the surface but no span for the solid.
                (a, b) => assert!(matches!(leaf, Leaf::Sphere | Leaf::Torus | Leaf::Cone), "{leaf:?}: {a:?} vs {b:?}"),
            }
        }
    }
}

fn node(kind: NodeKind, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind, origin: "test".into() }
}

fn shape(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    node(NodeKind::Shape { shape, material }, transform)
}

fn csg(op: SetOp, children: Vec<NodeDesc>) -> NodeKind {
    NodeKind::Solid(SolidDesc::Csg { op, children })
}

/// A cube with a ball carved out of its front face: every face's normal points out of
/// the result, and each surface keeps its leaf's material.
#[test]
fn carved_faces_flip_and_keep_their_material() {
    let carved = node(
        csg(
            SetOp::Difference,
            vec![shape(ShapeDesc::Cube, 1, vec![]), shape(ShapeDesc::Sphere, 2, vec![TransformOp::Translate(Vec3::Z)])],
        ),
        vec![],
    );
    let scene = scene_of(vec![carved]);
    // Straight into the crater: the sphere's surface, seen from inside the sphere.
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z);
    let hit = scene.intersect(&ray, f32::INFINITY).expect("hits the crater floor");
    assert!((hit.t - 5.0).abs() < 1e-5, "{}", hit.t);
    assert!((hit.normal - Vec3::Z).length() < 1e-5, "{}", hit.normal);
    assert_eq!(hit.material, 2);
    // Beside the crater: the cube's front face.
    let ray = Ray::new(Vec3::new(0.9, 0.9, 5.0), Vec3::NEG_Z);
    let hit = scene.intersect(&ray, f32::INFINITY).unwrap();
    assert!((hit.t - 4.0).abs() < 1e-5 && hit.normal == Vec3::Z && hit.material == 1);
    // The crater's sloping wall: the ball's normal, reversed.
    let ray = Ray::new(Vec3::new(0.5, 0.0, 5.0), Vec3::NEG_Z);
    let hit = scene.intersect(&ray, f32::INFINITY).unwrap();
    let want = 1.0 - 0.75f32.sqrt();
    assert!((hit.point.z - want).abs() < 1e-5, "{}", hit.point);
    assert!((hit.normal - Vec3::new(-0.5, 0.0, 0.75f32.sqrt())).length() < 1e-5 && hit.material == 2, "{hit:?}");
    // From inside the solid (behind the crater), the exit through the crater is flipped
    // too: it points along the ray.
    let ray = Ray::new(Vec3::new(0.0, 0.0, -0.5), Vec3::Z);
    let hit = scene.intersect(&ray, f32::INFINITY).unwrap();
    assert!((hit.t - 0.5).abs() < 1e-5 && hit.normal.z > 0.99, "{hit:?}");
}

/// The box of an intersection is the overlap of its children's, and a difference's is
/// its first child's, so the BVH gets tight boxes.
#[test]
fn bounds_are_tight() {
    let a = shape(ShapeDesc::Cube, 0, vec![TransformOp::Translate(Vec3::new(-0.5, 0.0, 0.0))]);
    let b = shape(ShapeDesc::Cube, 0, vec![TransformOp::Translate(Vec3::new(0.5, 0.0, 0.0))]);
    let inter = scene_of(vec![node(csg(SetOp::Intersection, vec![a.clone(), b.clone()]), vec![])]);
    let bounds = inter.bvh.bounds();
    assert!((bounds.min - Vec3::new(-0.5, -1.0, -1.0)).length() < 1e-6, "{bounds:?}");
    assert!((bounds.max - Vec3::new(0.5, 1.0, 1.0)).length() < 1e-6, "{bounds:?}");
    let diff = scene_of(vec![node(csg(SetOp::Difference, vec![a.clone(), b.clone()]), vec![])]);
    let bounds = diff.bvh.bounds();
    assert!((bounds.max.x - 0.5).abs() < 1e-6 && (bounds.min.x + 1.5).abs() < 1e-6, "{bounds:?}");
    // A plane cut gives a bounded solid.
    let cut = scene_of(vec![node(csg(SetOp::Intersection, vec![a, shape(ShapeDesc::Plane, 0, vec![])]), vec![])]);
    assert_eq!(cut.bounded_count, 1);
    // Disjoint: nothing to place.
    let far = shape(ShapeDesc::Sphere, 0, vec![TransformOp::Translate(Vec3::new(5.0, 0.0, 0.0))]);
    let empty = scene_of(vec![node(csg(SetOp::Intersection, vec![b, far]), vec![])]);
    assert!(empty.instances.is_empty());
}

#[test]
fn invalid_csg_is_refused_with_the_node_origin() {
    let compile_one = |kind: NodeKind| {
        let desc = SceneDesc {
            materials: materials(),
            objects: vec![NodeDesc { transform: vec![], kind, origin: "scene.glint:3:1".into() }],
            ..Default::default()
        };
        compile(&desc).expect_err("invalid").to_string()
    };
    assert!(compile_one(csg(SetOp::Union, vec![])).starts_with("scene.glint:3:1: union has no children"));
    let disk = NodeDesc {
        transform: vec![],
        kind: NodeKind::Shape { shape: ShapeDesc::Disk, material: 0 },
        origin: "scene.glint:4:3".into(),
    };
    let message = compile_one(csg(SetOp::Difference, vec![shape(ShapeDesc::Cube, 0, vec![]), disk]));
    assert!(message.starts_with("scene.glint:4:3: a disk has no inside"), "{message}");
    let bad = NodeKind::Solid(SolidDesc::Implicit {
        implicit: ImplicitDesc { function: "x^2 + (y".into(), bounds: [Vec3::splat(-1.0), Vec3::ONE], lipschitz: None },
        material: 0,
    });
    let message = compile_one(bad);
    assert!(message.contains("column 9 of the expression"), "{message}");
    let steep = NodeKind::Solid(SolidDesc::Implicit {
        implicit: ImplicitDesc {
            function: "10*x".into(),
            bounds: [Vec3::splat(-1.0), Vec3::ONE],
            lipschitz: Some(2.0),
        },
        material: 0,
    });
    assert!(compile_one(steep).contains("lipschitz 2 is too small"));
}

fn render_pixels(desc: &SceneDesc) -> glint_core::film::Image {
    let scene = compile(desc).expect("valid scene");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled").0
}

fn glass(transmissive: Vec3, ior: f32) -> MaterialDesc {
    MaterialDesc {
        name: "glass".into(),
        diffuse: Vec3::ZERO,
        specular: Vec3::ONE,
        transmissive,
        reflective: Some(Vec3::splat(0.05)),
        ior,
        ..Default::default()
    }
}

/// A biconvex lens about the origin, axis along z: the intersection of two balls of
/// radius 2 whose centres lie 1.5 either side (1 thick, rim radius √1.75 ≈ 1.32).
fn lens(material: usize, at: Vec3) -> NodeDesc {
    let ball = |z: f32| {
        shape(
            ShapeDesc::Sphere,
            material,
            vec![TransformOp::Scale(Vec3::splat(2.0)), TransformOp::Translate(Vec3::new(0.0, 0.0, z))],
        )
    };
    node(csg(SetOp::Intersection, vec![ball(-1.5), ball(1.5)]), vec![TransformOp::Translate(at)])
}

/// A union of one sphere renders like the sphere.
#[test]
fn a_union_of_one_ball_renders_like_the_ball() {
    let light = LightDesc::Point { position: Vec3::new(2.0, 4.0, 3.0), color: Vec3::ONE, attenuation: Vec3::X };
    let base = SceneDesc {
        settings: RenderSettings { width: 48, height: 36, ..Default::default() },
        lights: vec![light],
        materials: vec![
            MaterialDesc { name: "floor".into(), diffuse: Vec3::splat(0.8), ..Default::default() },
            glass(Vec3::new(0.9, 0.8, 0.7), 1.5),
        ],
        ..Default::default()
    };
    let floor = shape(ShapeDesc::Plane, 0, vec![TransformOp::Translate(Vec3::new(0.0, -1.0, 0.0))]);
    let ball = shape(ShapeDesc::Sphere, 1, vec![]);
    let plain = render_pixels(&SceneDesc { objects: vec![floor.clone(), ball.clone()], ..base.clone() });
    let wrapped =
        render_pixels(&SceneDesc { objects: vec![floor, node(csg(SetOp::Union, vec![ball]), vec![])], ..base });
    assert!(plain.mean_abs_diff(&wrapped) < 2e-3, "{}", plain.mean_abs_diff(&wrapped));
}

/// A glass CSG lens hung above a grey floor casts a shadow tinted by its transmissive
/// colour: under it the floor keeps more red than green and more green than blue, and
/// stays lit (a transparent occluder attenuates, it does not block).
#[test]
fn a_glass_csg_lens_casts_a_coloured_shadow() {
    let base = SceneDesc {
        settings: RenderSettings { width: 48, height: 36, ..Default::default() },
        // Straight above the lens, so the shadow ray from the floor under it crosses the glass.
        lights: vec![LightDesc::Point { position: Vec3::new(0.0, 10.0, 0.0), color: Vec3::ONE, attenuation: Vec3::X }],
        // Looking down at the floor under the lens, with the lens itself out of the frame.
        camera: CameraDesc { eye: Vec3::new(0.0, 0.5, 4.0), look: Vec3::new(0.0, -1.5, -4.0), ..Default::default() },
        materials: vec![
            MaterialDesc { name: "floor".into(), diffuse: Vec3::splat(0.8), ..Default::default() },
            glass(Vec3::new(0.9, 0.6, 0.3), 1.5),
        ],
        ..Default::default()
    };
    let floor = shape(ShapeDesc::Plane, 0, vec![TransformOp::Translate(Vec3::new(0.0, -1.0, 0.0))]);
    let lit = render_pixels(&SceneDesc { objects: vec![floor.clone()], ..base.clone() });
    let shadowed = render_pixels(&SceneDesc { objects: vec![floor, lens(1, Vec3::new(0.0, 3.0, 0.0))], ..base });
    for y in 0..36 {
        for x in 0..48 {
            assert!(shadowed.get(x, y).is_finite(), "pixel {x},{y}");
        }
    }
    // The image centre sees the floor point straight under the lens.
    let (lit, shadowed) = (lit.get(24, 18), shadowed.get(24, 18));
    assert!(lit.x > 0.1 && (lit.x - lit.z).abs() < 1e-4, "the unshadowed floor is grey and lit: {lit}");
    let kept = shadowed / lit;
    assert!(kept.max_element() < 0.95, "the lens casts no shadow: {shadowed} against {lit}");
    assert!(kept.x > 0.3, "the glass blocks the light instead of tinting it: {kept}");
    assert!(kept.x > kept.y + 0.05 && kept.y > kept.z + 0.05, "the shadow is not tinted like the glass: {kept}");
}

/// A converging CSG lens inverts what lies beyond its image point: through glass of
/// index 1 the camera sees a red wall on the left and a blue one on the right; through
/// the same lens of index 1.5 the two sides swap.
///
/// The lens (f ≈ 2.2 by the lensmaker's equation) is 5 from the camera, so rays from
/// the camera cross about 3.9 behind it, before they reach the wall at 6.
#[test]
fn a_glass_csg_lens_refracts_and_inverts() {
    let render_with_ior = |ior: f32| {
        let wall = |material: usize, x: f32| {
            shape(
                ShapeDesc::Cube,
                material,
                vec![TransformOp::Scale(Vec3::new(5.0, 5.0, 0.1)), TransformOp::Translate(Vec3::new(x, 0.0, -6.0))],
            )
        };
        render_pixels(&SceneDesc {
            settings: RenderSettings { width: 48, height: 36, ..Default::default() },
            lights: vec![LightDesc::Point {
                position: Vec3::new(0.0, 3.0, 5.0),
                color: Vec3::ONE,
                attenuation: Vec3::X,
            }],
            materials: vec![
                MaterialDesc { name: "red".into(), diffuse: Vec3::new(0.9, 0.05, 0.05), ..Default::default() },
                MaterialDesc { name: "blue".into(), diffuse: Vec3::new(0.05, 0.05, 0.9), ..Default::default() },
                glass(Vec3::splat(0.9), ior),
            ],
            objects: vec![wall(0, -5.0), wall(1, 5.0), lens(2, Vec3::ZERO)],
            ..Default::default()
        })
    };
    let straight = render_with_ior(1.0);
    let refracted = render_with_ior(1.5);
    // Six pixels either side of the centre: 0.7 off the axis at the lens, inside its rim.
    let (left, right) = ((18, 18), (30, 18));
    let red = |c: Vec3| c.x > 2.0 * c.z;
    let blue = |c: Vec3| c.z > 2.0 * c.x;
    assert!(red(straight.get(left.0, left.1)), "{}", straight.get(left.0, left.1));
    assert!(blue(straight.get(right.0, right.1)), "{}", straight.get(right.0, right.1));
    assert!(blue(refracted.get(left.0, left.1)), "{}", refracted.get(left.0, left.1));
    assert!(red(refracted.get(right.0, right.1)), "{}", refracted.get(right.0, right.1));
    // Outside the lens nothing changes.
    assert!(straight.get(2, 18).abs_diff_eq(refracted.get(2, 18), 1e-5));
    assert!(straight.get(45, 18).abs_diff_eq(refracted.get(45, 18), 1e-5));
}

/// Shadow rays see the carved solid: light passes through a hole drilled through a slab
/// and is blocked beside it.
#[test]
fn shadows_pass_through_carved_holes() {
    let slab = node(
        csg(
            SetOp::Difference,
            vec![
                shape(ShapeDesc::Cube, 0, vec![TransformOp::Scale(Vec3::new(2.0, 0.1, 2.0))]),
                shape(ShapeDesc::Cylinder, 0, vec![TransformOp::Scale(Vec3::new(0.5, 1.0, 0.5))]),
            ],
        ),
        vec![TransformOp::Translate(Vec3::new(0.0, 1.0, 0.0))],
    );
    let scene = scene_of(vec![slab]);
    let up = Vec3::Y;
    // From the floor straight up: through the hole, then beside it.
    assert!(!scene.occluded(&Ray::new(Vec3::new(0.2, 0.0, 0.1), up), 10.0));
    assert!(scene.occluded(&Ray::new(Vec3::new(1.0, 0.0, 0.0), up), 10.0));
    // A slanted ray that enters the hole but leaves through its wall is blocked.
    // (At y = 0.9 it is at x = 0.3, in the hole; it meets the wall x = 0.5 at y = 1.)
    assert!(scene.occluded(&Ray::new(Vec3::new(-1.5, 0.0, 0.0), Vec3::new(2.0, 1.0, 0.0)), 10.0));
    assert!(!scene.occluded(&Ray::new(Vec3::new(-0.3, 0.0, 0.0), Vec3::new(0.6, 1.0, 0.0)), 10.0));
    // Inside the hole the wall's normal faces the axis (out of the solid, into the hole).
    let hit = scene.intersect(&Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::X), 10.0).expect("hits the wall");
    assert!((hit.t - 0.5).abs() < 1e-5 && hit.normal.x < -0.99, "{hit:?}");
}
