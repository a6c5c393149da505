//! The allocator's settings. The binary and the benchmarks allocate through mimalloc
//! (see `main.rs`); this tunes it, and the pages the kernel gives it, for the solver's
//! pattern of allocation and the layer search's.

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

/// Turns transparent huge pages off for this process (`PR_SET_THP_DISABLE`, as mimalloc's
/// own `allow_thp=0` would at start-up), so memory is faulted in 4 KiB pages. mimalloc
/// asks for huge pages on its arenas (`MADV_HUGEPAGE`), and on a machine whose kernel
/// compacts and zeroes a 2 MiB page at the first touch of its arena, that is slow: the
/// layer search of Kamiya's Ryujin 2.1 (0.4 GB) spent 5.1–5.3 s of system time among
/// 15.6–16.2 s, against 0.3 s among 10.3 s with huge pages off, and the Japanese Spiny
/// Lobster v2 (1.2 GB) 49 s against 30 s (`crease verify`, one core, 2-core VM). The
/// solver's steps, whose memory is reused from step to step, take about as long either
/// way (10k vertices: 26–29 against 30–31 ms a step), and the studio's bench shows a
/// 10k-vertex drag at 6.0–7.4 frames a second against 2.9–4.1. The kernel passes the
/// setting on to child processes (the browser `crease studio` opens), where it changes
/// only the size of their pages. Returns whether the setting took.
pub fn no_huge_pages() -> bool {
    #[cfg(target_os = "linux")]
    {
        nix::sys::prctl::set_thp_disable(true).is_ok()
    }
    #[cfg(not(target_os = "linux"))]
    {
        false
    }
}

/// What a process that allocates through mimalloc (the binary, the solver and studio
/// benches) sets first: [`keep_freed_memory`] and [`no_huge_pages`], so the benches
/// measure the allocation the binary does.
pub fn set_up() {
    keep_freed_memory();
    no_huge_pages();
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

    #[cfg(target_os = "linux")]
    #[test]
    fn huge_pages_are_turned_off_for_the_process() {
        assert!(no_huge_pages());
        assert_eq!(nix::sys::prctl::get_thp_disable(), Ok(true));
    }
}
