//! With a pool of one thread, `pool::hot` still runs its computation on that thread, where the
//! computation's parallel sections run inline: from another thread each section would be
//! handed over to the worker and waited for (the engagement at 1,000 locations took 1.24–1.31 s
//! that way instead of 0.97 s). The global pool is set once per process, hence a file of its
//! own with one test.

use rayon::prelude::*;
use swarf_stock::pool::hot;

#[test]
fn with_one_thread_hot_runs_on_the_worker_and_its_sections_inline() {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .unwrap();
    assert_eq!(rayon::current_thread_index(), None, "the test's own thread");
    let (worker, sections) = hot(|| {
        let worker = rayon::current_thread_index();
        // Every item of a parallel section runs on the same thread as the computation.
        let sections: Vec<Option<usize>> = (0..64)
            .into_par_iter()
            .map(|_| rayon::current_thread_index())
            .collect();
        (worker, sections)
    });
    assert_eq!(worker, Some(0));
    assert!(sections.iter().all(|&t| t == worker));
}
