//! The allocator's settings. The binary and the benchmarks allocate through mimalloc
//! (see `main.rs`); this tunes it for the solver's pattern of allocation.

/// mimalloc's `mi_option_purge_delay`: slot 15 of `mi_option_t` in mimalloc 2 and 3 (3
/// is the one built), whose retired options keep their slots so the numbering stays. `libmimalloc-sys`
/// names the options on either side (`mi_option_eager_commit_delay` = 14,
/// `mi_option_use_numa_nodes` = 16) but not this one.
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// Keeps the memory the process frees for its own reuse instead of returning it to the
/// system a second later (mimalloc 3's default). A design step on a 100k-vertex sheet
/// builds and drops some 40 MB of rows and vectors each Newton iteration, and a
/// refactorisation some 300 MB every 48 steps; taking them back from the kernel page by
/// page cost 3–6% of a step (Miura drag, one core, alternating runs: 324–338 against
/// 336–358 ms; 371–382 with a 10 ms delay). The price: a process keeps its peak memory
/// until it ends.
pub fn keep_freed_memory() {
    // SAFETY: mi_option_set stores one value in mimalloc's option table; any slot below
    // `_mi_option_last` is valid and 15 is.
    unsafe { libmimalloc_sys::mi_option_set(MI_OPTION_PURGE_DELAY, -1) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slot_15_is_the_purge_delay_and_takes_the_setting() {
        // SAFETY: reads of mimalloc's option table.
        let get = || unsafe { libmimalloc_sys::mi_option_get(MI_OPTION_PURGE_DELAY) };
        // The purge delay's default in mimalloc 3 (ms); its neighbours default to 1 (the
        // eager-commit delay) and 0 (NUMA nodes), so a shifted table would show here.
        assert_eq!(get(), 1000);
        keep_freed_memory();
        assert_eq!(get(), -1);
    }
}
