//! Resuming from a checkpoint: a render interrupted after some tiles, saved, restored
//! and finished gives the uninterrupted image bit for bit; a checkpoint that is
//! damaged or made for another scene is refused.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::Vec3;
use glint_core::desc::*;
use std::collections::BTreeSet;

use glint_core::render::{
    CheckpointError, RenderError, RenderStats, TileStore, checkpoint_header, render, render_resumable, tile_count,
};
use glint_core::scene::{RenderScene, compile};

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// Two spheres on a plane, with glass, a wide filter (tiles overlap) and AOVs.
fn scene(integrator: IntegratorDesc, adaptive: Option<AdaptiveDesc>) -> RenderScene {
    let glass =
        MaterialDesc { diffuse: Vec3::splat(0.1), transmissive: Vec3::splat(0.8), ior: 1.5, ..Default::default() };
    let desc = SceneDesc {
        settings: RenderSettings {
            width: 40,
            height: 36,
            filter: FilterDesc { kind: FilterKind::Gaussian, radius: 1.5 },
            integrator,
            adaptive,
            spp: Some(4),
            ..Default::default()
        },
        camera: CameraDesc { eye: Vec3::new(0.0, 1.0, 6.0), look: Vec3::NEG_Z, up: Vec3::Y, ..Default::default() },
        lights: vec![LightDesc::Point { position: Vec3::new(2.0, 4.0, 3.0), color: Vec3::ONE, attenuation: Vec3::X }],
        materials: vec![MaterialDesc { diffuse: Vec3::new(0.7, 0.3, 0.2), ..Default::default() }, glass],
        textures: vec![],
        objects: vec![
            node(ShapeDesc::Plane, 0, vec![TransformOp::Translate(Vec3::new(0.0, -1.0, 0.0))]),
            node(ShapeDesc::Sphere, 0, vec![TransformOp::Translate(Vec3::new(-1.2, 0.0, 0.0))]),
            node(ShapeDesc::Sphere, 1, vec![TransformOp::Translate(Vec3::new(1.2, 0.0, 0.5))]),
        ],
        meshes: vec![],
        views: vec![],
    };
    let mut scene = compile(&desc).expect("valid scene");
    scene.settings.aovs = true;
    scene
}

/// Renders until `tiles` tiles are done, then cancels: what a kill leaves behind.
fn interrupted(scene: &RenderScene, tiles: usize) -> TileStore {
    let store = TileStore::default();
    let cancel = AtomicBool::new(false);
    let finished = AtomicUsize::new(0);
    let result = render_resumable(
        scene,
        &store,
        &|_, _| {
            if finished.fetch_add(1, Ordering::Relaxed) + 1 >= tiles {
                cancel.store(true, Ordering::Relaxed);
            }
        },
        &cancel,
    );
    assert_eq!(result.err(), Some(RenderError::Cancelled));
    store
}

fn assert_bit_identical(a: &(glint_core::film::Image, RenderStats), b: &(glint_core::film::Image, RenderStats)) {
    let bits = |image: &glint_core::film::Image| {
        image.pixels.iter().flat_map(|p| p.to_array()).map(f32::to_bits).collect::<Vec<_>>()
    };
    assert_eq!(bits(&a.0), bits(&b.0), "colour differs");
    assert_eq!(a.1, b.1, "statistics or AOVs differ");
}

#[test]
fn a_resumed_render_is_bit_identical_to_an_uninterrupted_one() {
    let cases = [
        ("whitted", IntegratorDesc::Whitted, None),
        ("path", IntegratorDesc::Path(PathDesc::default()), None),
        ("adaptive", IntegratorDesc::Whitted, Some(AdaptiveDesc { min_samples: 2, max_samples: 16, threshold: 0.02 })),
    ];
    for (name, integrator, adaptive) in cases {
        let scene = scene(integrator, adaptive);
        let whole = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
        let total = tile_count(&scene) as usize;
        let partial = interrupted(&scene, total / 3);
        assert!(!partial.is_empty() && partial.len() < total, "{name}: {} of {total} tiles", partial.len());
        let fingerprint = 0x5eed;
        let bytes = journal(&partial, &scene, fingerprint);
        let restored = TileStore::from_checkpoint(&bytes, &scene, fingerprint).expect("reads back");
        assert_eq!((restored.store.len(), restored.valid_len), (partial.len(), bytes.len()));
        let restored = restored.store;
        let traced = AtomicUsize::new(0);
        let resumed = render_resumable(
            &scene,
            &restored,
            &|_, _| {
                traced.fetch_add(1, Ordering::Relaxed);
            },
            &AtomicBool::new(false),
        )
        .expect("finishes");
        assert_eq!(traced.into_inner(), total - partial.len(), "{name}: the resumed render retraced saved tiles");
        assert_bit_identical(&resumed, &whole);
        // Saving the full store and restoring it gives the image without tracing.
        let full = TileStore::from_checkpoint(&journal(&restored, &scene, fingerprint), &scene, fingerprint)
            .expect("reads back")
            .store;
        let again = render_resumable(&scene, &full, &|_, _| panic!("nothing left to trace"), &AtomicBool::new(false))
            .expect("finishes");
        assert_bit_identical(&again, &whole);
    }
}

/// A checkpoint as the CLI writes it: the header, then records appended save by save.
fn journal(store: &TileStore, scene: &RenderScene, fingerprint: u64) -> Vec<u8> {
    let mut bytes = checkpoint_header(scene, fingerprint);
    bytes.extend(store.new_records(&mut BTreeSet::new()));
    bytes
}

#[test]
fn appended_saves_write_each_tile_once() {
    let scene = scene(IntegratorDesc::Whitted, None);
    let store = interrupted(&scene, 4);
    let mut written = BTreeSet::new();
    let first = store.new_records(&mut written);
    assert_eq!(written, store.indices());
    assert!(store.new_records(&mut written).is_empty(), "nothing new, nothing written");
    let resumed = render_resumable(&scene, &store, &|_, _| {}, &AtomicBool::new(false)).expect("finishes");
    let mut bytes = checkpoint_header(&scene, 1);
    bytes.extend(first);
    bytes.extend(store.new_records(&mut written));
    assert_eq!(written.len(), tile_count(&scene) as usize);
    let restored = TileStore::from_checkpoint(&bytes, &scene, 1).expect("reads back").store;
    let again = render_resumable(&scene, &restored, &|_, _| panic!("all saved"), &AtomicBool::new(false));
    assert_bit_identical(&again.expect("finishes"), &resumed);
}

#[test]
fn a_torn_journal_keeps_the_whole_records_before_the_tear() {
    let scene = scene(IntegratorDesc::Whitted, None);
    let whole = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    let saved = interrupted(&scene, 6);
    let bytes = journal(&saved, &scene, 7);
    let header = checkpoint_header(&scene, 7).len();
    let mut kept_before = usize::MAX;
    // A crash can cut the file anywhere after the header, or leave garbage in the tail.
    for cut in (header + 1..bytes.len()).step_by(211) {
        let restored = TileStore::from_checkpoint(&bytes[..cut], &scene, 7).expect("the header is whole");
        assert!(restored.valid_len <= cut && restored.valid_len >= header);
        assert!(restored.store.len() < saved.len(), "a cut record was kept");
        assert!(kept_before == usize::MAX || restored.store.len() >= kept_before, "a longer prefix kept fewer tiles");
        kept_before = restored.store.len();
        let mut flipped = bytes[..cut].to_vec();
        flipped[cut - 1] ^= 0x10;
        let damaged = TileStore::from_checkpoint(&flipped, &scene, 7).expect("the header is whole").store;
        let resumed = render_resumable(&scene, &damaged, &|_, _| {}, &AtomicBool::new(false)).expect("finishes");
        assert_bit_identical(&resumed, &whole);
    }
}

#[test]
fn a_checkpoint_for_something_else_or_with_a_damaged_header_is_refused() {
    let scene = scene(IntegratorDesc::Whitted, None);
    let bytes = journal(&interrupted(&scene, 5), &scene, 7);
    let error =
        |bytes: &[u8], scene: &RenderScene, fingerprint| TileStore::from_checkpoint(bytes, scene, fingerprint).err();
    assert_eq!(error(&bytes, &scene, 8), Some(CheckpointError::OtherScene));
    assert_eq!(error(b"P6\n1 1\n255\n", &scene, 7), Some(CheckpointError::NotACheckpoint));
    let mut wider = scene.clone();
    wider.settings.width += 16;
    assert_eq!(error(&bytes, &wider, 7), Some(CheckpointError::OtherScene));
    let mut no_aovs = scene.clone();
    no_aovs.settings.aovs = false;
    assert_eq!(error(&bytes, &no_aovs, 7), Some(CheckpointError::OtherScene));
    let header = checkpoint_header(&scene, 7).len();
    for at in 12..header {
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x01;
        assert_eq!(error(&flipped, &scene, 7), Some(CheckpointError::Damaged), "flip at {at}");
    }
    assert_eq!(error(&bytes[..header - 1], &scene, 7), Some(CheckpointError::Damaged));
}

#[test]
fn the_fingerprint_follows_every_change_to_the_description() {
    let desc = SceneDesc::default();
    let mut other = desc.clone();
    other.settings.seed += 1;
    assert_ne!(desc.fingerprint(), other.fingerprint());
    let mut nudged = desc.clone();
    nudged.camera.eye.x = f32::from_bits(nudged.camera.eye.x.to_bits() + 1);
    assert_ne!(desc.fingerprint(), nudged.fingerprint(), "one ulp of the camera");
    assert_eq!(desc.fingerprint(), desc.clone().fingerprint());
}
