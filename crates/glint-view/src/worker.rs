//! The render thread: runs the viewer's passes one after another on the rayon pool, so
//! the thread that handles input never waits for a render.

use std::sync::mpsc::{Sender, channel};
use std::thread::JoinHandle;

use crate::pass::{Finished, Job};
use crate::runner::Runner;

/// A thread that runs each [`Job`] it is sent and hands the result to a callback.
pub struct Worker {
    jobs: Option<Sender<Job>>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the thread, which runs jobs with `runner`; `done` gets every result
    /// (`None`: the job was cancelled).
    pub fn spawn(mut runner: Runner, done: impl Fn(Option<Finished>) + Send + 'static) -> Self {
        let (jobs, inbox) = channel::<Job>();
        let thread = std::thread::Builder::new()
            .name("glint-view render".into())
            .spawn(move || {
                for job in inbox {
                    done(runner.run(&job));
                }
            })
            .expect("the OS refused to start the render thread");
        Self { jobs: Some(jobs), thread: Some(thread) }
    }

    /// Queues `job`.
    pub fn send(&self, job: Job) {
        if let Some(jobs) = &self.jobs {
            // The thread ends only when the sender is dropped: sending cannot fail.
            let _ = jobs.send(job);
        }
    }
}

impl Drop for Worker {
    /// Closes the queue and waits for the pass in flight (cancelled by the viewer).
    fn drop(&mut self) {
        self.jobs.take();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
