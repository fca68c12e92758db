//! Slow studies (noise seeds, manoeuvre tables) spread over the two cores CI has.

/// `f(worker, k)` for k in 0..n on two threads, worker 0 taking the even k and worker 1 the
/// odd ones (a worker's own scratch space can be picked by its index); the results in the
/// order of k.
pub fn on_two_threads<T: Send>(n: usize, f: impl Fn(usize, usize) -> T + Sync) -> Vec<T> {
    let f = &f;
    let mut out: Vec<(usize, T)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|w| {
                s.spawn(move || {
                    (0..n)
                        .filter(|k| k % 2 == w)
                        .map(|k| (k, f(w, k)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    out.sort_by_key(|(k, _)| *k);
    out.into_iter().map(|(_, t)| t).collect()
}
