//! `glint view --no-window`: the viewer's passes without a display — to write what the
//! window would show, print a pixel's ray tree, or measure the viewer's speed.

use std::sync::mpsc::channel;
use std::time::{Duration, Instant};

use crate::draw::compose;
use crate::pass::PassKind;
use crate::viewer::{Input, Viewer};
use crate::worker::Worker;
use crate::{ViewArgs, explain};

/// One-sample passes timed for the frame rate.
const BENCH_PASSES: u32 = 20;
/// Inputs timed for the latency.
const BENCH_INPUTS: u32 = 10;

/// Renders `args.frames` passes, prints `--explain`'s tree, writes `--output`; with
/// `--bench`, measures instead.
///
/// # Errors
///
/// The image could not be written.
pub fn run(mut viewer: Viewer, args: &ViewArgs) -> Result<(), String> {
    if args.bench {
        return bench(viewer);
    }
    while viewer.passes() < args.frames && viewer.step() {}
    if let Some(explained) = args.explain.and_then(|(x, y)| viewer.explain(x, y).cloned()) {
        let scene = viewer.scene().lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        print!("{}", explain::describe(&explained.tree, (explained.x, explained.y), &scene, viewer.desc()));
    }
    viewer.save(&args.output)?;
    eprintln!("glint view: wrote {} ({} passes)", args.output.display(), viewer.passes());
    Ok(())
}

/// Prints one JSON object: one-sample passes per second (with and without composing
/// the window's picture), and the time from an input to its first picture and to its
/// first full one-sample frame, an input arriving while a pass is in flight as it does
/// in the window.
fn bench(mut viewer: Viewer) -> Result<(), String> {
    while viewer.passes() < 1 && viewer.step() {}
    let (mut rendering, mut composing) = (Duration::ZERO, Duration::ZERO);
    for _ in 0..BENCH_PASSES {
        let start = Instant::now();
        viewer.step();
        rendering += start.elapsed();
        let start = Instant::now();
        std::hint::black_box(compose(&viewer));
        composing += start.elapsed();
    }
    let passes = f64::from(BENCH_PASSES);
    let rays_per_second = viewer.timing().rays_per_second;
    let (first_picture, first_frame) = latency(viewer);
    println!(
        "{{\"passes_per_second\": {:.2}, \"frames_per_second\": {:.2}, \"input_to_picture_ms\": {:.1}, \"input_to_full_frame_ms\": {:.1}, \"mrays_per_second\": {:.2}}}",
        passes / rendering.as_secs_f64(),
        passes / (rendering + composing).as_secs_f64(),
        first_picture.as_secs_f64() * 1e3,
        first_frame.as_secs_f64() * 1e3,
        rays_per_second / 1e6,
    );
    Ok(())
}

/// Median times from an orbit input (sent mid-pass) to the first picture of the new
/// view (a preview, composed) and to its first one-sample frame.
fn latency(mut viewer: Viewer) -> (Duration, Duration) {
    let (done, results) = channel();
    let worker = Worker::spawn(crate::runner::Runner::new(viewer.gpu()), move |finished| {
        let _ = done.send(finished);
    });
    let (mut pictures, mut frames) = (Vec::new(), Vec::new());
    for _ in 0..BENCH_INPUTS {
        if let Some(job) = viewer.next_job() {
            worker.send(job);
        }
        // Let the accumulating pass get going, as it usually is when the user acts.
        std::thread::sleep(Duration::from_millis(20));
        let input = Instant::now();
        viewer.handle(Input::Orbit { dx: 4.0, dy: 0.0 });
        let mut picture = None;
        while let Ok(finished) = results.recv() {
            let shown = viewer.finish(finished);
            if shown.is_some() && picture.is_none() {
                std::hint::black_box(compose(&viewer));
                picture = Some(input.elapsed());
            }
            if shown == Some(PassKind::Sample(0)) {
                frames.push(input.elapsed());
                break;
            }
            match viewer.next_job() {
                Some(job) => worker.send(job),
                None => break,
            }
        }
        pictures.extend(picture);
    }
    (median(pictures), median(frames))
}

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times.get(times.len() / 2).copied().unwrap_or_default()
}
