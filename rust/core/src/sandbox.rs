//! The kernel layers of the skill sandbox: seccomp programs and Landlock.
//!
//! A skill runs in a process that bubblewrap puts in its own user, mount, PID, network,
//! IPC and UTS namespaces (the host side, `skillwright.runtime.sandbox`, builds that). This
//! module adds what bubblewrap takes as input or leaves to the process itself:
//!
//! * [`base_program`]: the system calls the sandboxed interpreter may make at all (an
//!   allow-list; anything else fails with `EPERM`). It is loaded by bubblewrap before the
//!   interpreter starts. Sockets are `AF_UNIX` only (the runtime's channel to the host is a
//!   socket pair), `clone` may not create namespaces, and `ioctl` may not push input into a
//!   terminal (`TIOCSTI`, `TIOCLINUX`). Left out, among others: `ptrace`, `process_vm_*`,
//!   `mount` and the new mount API, `unshare`, `setns`, `pivot_root`, `chroot`, `keyctl`,
//!   `add_key`, `bpf`, `perf_event_open`, `userfaultfd`, `io_uring_*`, module and `kexec`
//!   calls, `open_by_handle_at`, clock and host-name setters, `reboot`, `swapon`.
//! * [`fallback_program`]: `clone3` answers `ENOSYS`, so that the C library falls back to
//!   `clone`, whose flags a filter can read (`clone3` passes them in memory it cannot).
//! * [`confine_child`]: what one skill's process applies to itself once the fork server
//!   has forked it and before the skill's code is loaded: Landlock (write only in its own
//!   scratch folder, read only what the sandbox holds, no signals to and no abstract
//!   sockets of processes outside its domain, where the kernel has Landlock) and a third
//!   seccomp program that takes away what only the fork server needed: `fork`, `vfork`,
//!   `clone` of anything but a thread, `execve`, `execveat`, and signals to any process
//!   but itself.
//!
//! Filters stack: the kernel runs every program loaded and takes the strictest answer, so a
//! process can add restrictions and never remove one.

use std::collections::BTreeMap;
use std::path::PathBuf;

use landlock::{
    path_beneath_rules, Access, AccessFs, Ruleset, RulesetAttr, RulesetCreatedAttr, RulesetStatus,
    Scope, ABI,
};
use seccompiler::{
    BpfProgram, SeccompAction, SeccompCmpArgLen, SeccompCmpOp, SeccompCondition, SeccompFilter,
    SeccompRule, TargetArch,
};

use crate::{CoreError, CoreResult};

/// The Landlock ABI whose rights the sandbox asks for: V6 (Linux 6.12) adds the signal and
/// abstract-socket scopes. Older kernels enforce what they know (best effort), and the
/// status says how much that was.
const LANDLOCK_ABI: ABI = ABI::V6;

/// `ioctl` requests that write into a terminal's input queue or drive the console.
const TIOCSTI: u64 = 0x5412;
const TIOCLINUX: u64 = 0x541C;

/// `clone` flags that create namespaces (`CLONE_NEWTIME` exists only for `clone3`).
const NAMESPACE_FLAGS: u64 = (libc::CLONE_NEWNS
    | libc::CLONE_NEWCGROUP
    | libc::CLONE_NEWUTS
    | libc::CLONE_NEWIPC
    | libc::CLONE_NEWUSER
    | libc::CLONE_NEWPID
    | libc::CLONE_NEWNET) as u64;

/// System calls allowed with any arguments, on every architecture.
const ALLOWED: &[i64] = &[
    // files and folders (the mount namespace and Landlock decide which)
    libc::SYS_read,
    libc::SYS_write,
    libc::SYS_readv,
    libc::SYS_writev,
    libc::SYS_pread64,
    libc::SYS_pwrite64,
    libc::SYS_preadv,
    libc::SYS_pwritev,
    libc::SYS_preadv2,
    libc::SYS_pwritev2,
    libc::SYS_openat,
    libc::SYS_openat2,
    libc::SYS_close,
    libc::SYS_close_range,
    libc::SYS_newfstatat,
    libc::SYS_fstat,
    libc::SYS_statx,
    libc::SYS_statfs,
    libc::SYS_fstatfs,
    libc::SYS_lseek,
    libc::SYS_getdents64,
    libc::SYS_getcwd,
    libc::SYS_chdir,
    libc::SYS_fchdir,
    libc::SYS_renameat,
    libc::SYS_renameat2,
    libc::SYS_mkdirat,
    libc::SYS_unlinkat,
    libc::SYS_linkat,
    libc::SYS_symlinkat,
    libc::SYS_readlinkat,
    libc::SYS_fchmod,
    libc::SYS_fchmodat,
    libc::SYS_fchmodat2,
    libc::SYS_fchown,
    libc::SYS_fchownat,
    libc::SYS_umask,
    libc::SYS_utimensat,
    libc::SYS_faccessat,
    libc::SYS_faccessat2,
    libc::SYS_truncate,
    libc::SYS_ftruncate,
    libc::SYS_fsync,
    libc::SYS_fdatasync,
    libc::SYS_fallocate,
    libc::SYS_fadvise64,
    libc::SYS_flock,
    libc::SYS_fcntl,
    libc::SYS_dup,
    libc::SYS_dup3,
    libc::SYS_pipe2,
    libc::SYS_copy_file_range,
    libc::SYS_sendfile,
    libc::SYS_splice,
    libc::SYS_tee,
    libc::SYS_getxattr,
    libc::SYS_lgetxattr,
    libc::SYS_fgetxattr,
    libc::SYS_listxattr,
    libc::SYS_llistxattr,
    libc::SYS_flistxattr,
    libc::SYS_memfd_create,
    libc::SYS_inotify_init1,
    libc::SYS_inotify_add_watch,
    libc::SYS_inotify_rm_watch,
    // memory
    libc::SYS_mmap,
    libc::SYS_munmap,
    libc::SYS_mprotect,
    libc::SYS_mremap,
    libc::SYS_madvise,
    libc::SYS_brk,
    libc::SYS_msync,
    libc::SYS_mincore,
    libc::SYS_membarrier,
    // signals (the child's own program narrows kill and tgkill to itself)
    libc::SYS_rt_sigaction,
    libc::SYS_rt_sigprocmask,
    libc::SYS_rt_sigreturn,
    libc::SYS_rt_sigpending,
    libc::SYS_rt_sigtimedwait,
    libc::SYS_rt_sigsuspend,
    libc::SYS_sigaltstack,
    libc::SYS_kill,
    libc::SYS_tgkill,
    // processes and threads (the fork server forks; its children may not)
    libc::SYS_clone3,
    libc::SYS_execve,
    libc::SYS_wait4,
    libc::SYS_waitid,
    libc::SYS_exit,
    libc::SYS_exit_group,
    libc::SYS_set_tid_address,
    libc::SYS_set_robust_list,
    libc::SYS_get_robust_list,
    libc::SYS_rseq,
    libc::SYS_futex,
    libc::SYS_futex_waitv,
    libc::SYS_prctl,
    libc::SYS_seccomp,
    libc::SYS_landlock_create_ruleset,
    libc::SYS_landlock_add_rule,
    libc::SYS_landlock_restrict_self,
    libc::SYS_getpid,
    libc::SYS_getppid,
    libc::SYS_gettid,
    libc::SYS_getuid,
    libc::SYS_geteuid,
    libc::SYS_getgid,
    libc::SYS_getegid,
    libc::SYS_getgroups,
    libc::SYS_getresuid,
    libc::SYS_getresgid,
    // the fork server drops from the user namespace's root to nobody with these; without
    // CAP_SETUID afterwards they can only set the ids a process already has
    libc::SYS_setuid,
    libc::SYS_setgid,
    libc::SYS_setgroups,
    libc::SYS_setresuid,
    libc::SYS_setresgid,
    libc::SYS_setreuid,
    libc::SYS_setregid,
    libc::SYS_getpgid,
    libc::SYS_setpgid,
    libc::SYS_getsid,
    libc::SYS_setsid,
    libc::SYS_capget,
    libc::SYS_capset,
    libc::SYS_getrlimit,
    libc::SYS_setrlimit,
    libc::SYS_prlimit64,
    libc::SYS_getrusage,
    libc::SYS_times,
    libc::SYS_getpriority,
    libc::SYS_setpriority,
    libc::SYS_sched_yield,
    libc::SYS_sched_getaffinity,
    libc::SYS_sched_setaffinity,
    libc::SYS_sched_getparam,
    libc::SYS_sched_getscheduler,
    libc::SYS_sched_get_priority_max,
    libc::SYS_sched_get_priority_min,
    libc::SYS_sched_getattr,
    libc::SYS_getcpu,
    libc::SYS_uname,
    libc::SYS_sysinfo,
    libc::SYS_getrandom,
    libc::SYS_restart_syscall,
    // time
    libc::SYS_clock_gettime,
    libc::SYS_clock_getres,
    libc::SYS_clock_nanosleep,
    libc::SYS_nanosleep,
    libc::SYS_gettimeofday,
    libc::SYS_getitimer,
    libc::SYS_setitimer,
    libc::SYS_timer_create,
    libc::SYS_timer_settime,
    libc::SYS_timer_gettime,
    libc::SYS_timer_getoverrun,
    libc::SYS_timer_delete,
    libc::SYS_timerfd_create,
    libc::SYS_timerfd_settime,
    libc::SYS_timerfd_gettime,
    // waiting on descriptors
    libc::SYS_ppoll,
    libc::SYS_pselect6,
    libc::SYS_epoll_create1,
    libc::SYS_epoll_ctl,
    libc::SYS_epoll_pwait,
    libc::SYS_epoll_pwait2,
    libc::SYS_eventfd2,
    libc::SYS_signalfd4,
    // sockets: socket() and socketpair() are AF_UNIX only (below)
    libc::SYS_connect,
    libc::SYS_accept4,
    libc::SYS_bind,
    libc::SYS_listen,
    libc::SYS_sendto,
    libc::SYS_recvfrom,
    libc::SYS_sendmsg,
    libc::SYS_recvmsg,
    libc::SYS_sendmmsg,
    libc::SYS_recvmmsg,
    libc::SYS_shutdown,
    libc::SYS_getsockname,
    libc::SYS_getpeername,
    libc::SYS_getsockopt,
    libc::SYS_setsockopt,
];

/// The older calls x86-64 still has (aarch64 and riscv64 only have their `*at` forms).
#[cfg(target_arch = "x86_64")]
const ALLOWED_LEGACY: &[i64] = &[
    libc::SYS_open,
    libc::SYS_creat,
    libc::SYS_stat,
    libc::SYS_lstat,
    libc::SYS_access,
    libc::SYS_pipe,
    libc::SYS_dup2,
    libc::SYS_rename,
    libc::SYS_mkdir,
    libc::SYS_rmdir,
    libc::SYS_unlink,
    libc::SYS_link,
    libc::SYS_symlink,
    libc::SYS_readlink,
    libc::SYS_chmod,
    libc::SYS_chown,
    libc::SYS_lchown,
    libc::SYS_utime,
    libc::SYS_utimes,
    libc::SYS_futimesat,
    libc::SYS_getdents,
    libc::SYS_fork,
    libc::SYS_vfork,
    libc::SYS_poll,
    libc::SYS_select,
    libc::SYS_epoll_create,
    libc::SYS_epoll_wait,
    libc::SYS_eventfd,
    libc::SYS_signalfd,
    libc::SYS_inotify_init,
    libc::SYS_time,
    libc::SYS_alarm,
    libc::SYS_pause,
    libc::SYS_getpgrp,
    libc::SYS_arch_prctl,
    libc::SYS_accept,
];
#[cfg(not(target_arch = "x86_64"))]
const ALLOWED_LEGACY: &[i64] = &[];

/// The processes-only calls a skill's process loses (its own program, on top of the base).
#[cfg(target_arch = "x86_64")]
const FORKS: &[i64] = &[libc::SYS_fork, libc::SYS_vfork];
#[cfg(not(target_arch = "x86_64"))]
const FORKS: &[i64] = &[];

fn arch() -> CoreResult<TargetArch> {
    TargetArch::try_from(std::env::consts::ARCH).map_err(|_| {
        CoreError::InvalidArgument(format!(
            "the sandbox has no seccomp program for the {} architecture",
            std::env::consts::ARCH
        ))
    })
}

fn seccomp_error(error: impl std::fmt::Display) -> CoreError {
    CoreError::InvalidArgument(format!("seccomp program: {error}"))
}

/// A condition on one argument of a call.
fn arg(
    index: u8,
    len: SeccompCmpArgLen,
    op: SeccompCmpOp,
    value: u64,
) -> CoreResult<SeccompCondition> {
    SeccompCondition::new(index, len, op, value).map_err(seccomp_error)
}

/// A rule that holds when every condition does.
fn when(conditions: Vec<SeccompCondition>) -> CoreResult<SeccompRule> {
    SeccompRule::new(conditions).map_err(seccomp_error)
}

fn compile(
    rules: BTreeMap<i64, Vec<SeccompRule>>,
    mismatch: SeccompAction,
    matched: SeccompAction,
) -> CoreResult<BpfProgram> {
    let filter = SeccompFilter::new(rules, mismatch, matched, arch()?).map_err(seccomp_error)?;
    filter.try_into().map_err(seccomp_error)
}

fn base_rules() -> CoreResult<BTreeMap<i64, Vec<SeccompRule>>> {
    let mut rules: BTreeMap<i64, Vec<SeccompRule>> = ALLOWED
        .iter()
        .chain(ALLOWED_LEGACY)
        .map(|&call| (call, Vec::new()))
        .collect();
    let unix = || {
        when(vec![arg(
            0,
            SeccompCmpArgLen::Dword,
            SeccompCmpOp::Eq,
            libc::AF_UNIX as u64,
        )?])
    };
    rules.insert(libc::SYS_socket, vec![unix()?]);
    rules.insert(libc::SYS_socketpair, vec![unix()?]);
    rules.insert(
        libc::SYS_clone,
        vec![when(vec![arg(
            0,
            SeccompCmpArgLen::Qword,
            SeccompCmpOp::MaskedEq(NAMESPACE_FLAGS),
            0,
        )?])?],
    );
    rules.insert(
        libc::SYS_ioctl,
        vec![when(vec![
            arg(1, SeccompCmpArgLen::Dword, SeccompCmpOp::Ne, TIOCSTI)?,
            arg(1, SeccompCmpArgLen::Dword, SeccompCmpOp::Ne, TIOCLINUX)?,
        ])?],
    );
    Ok(rules)
}

/// The allow-list every sandboxed process runs under: a system call it lists (with the
/// arguments it allows) goes through, any other fails with `EPERM`.
pub fn base_program() -> CoreResult<BpfProgram> {
    compile(
        base_rules()?,
        SeccompAction::Errno(libc::EPERM as u32),
        SeccompAction::Allow,
    )
}

/// `clone3` answers `ENOSYS` (the C library then uses `clone`); everything else passes.
pub fn fallback_program() -> CoreResult<BpfProgram> {
    let rules = BTreeMap::from([(libc::SYS_clone3, Vec::new())]);
    compile(
        rules,
        SeccompAction::Allow,
        SeccompAction::Errno(libc::ENOSYS as u32),
    )
}

/// What a skill's process `pid` gives up once forked: new processes, new programs, and
/// signals to anything but itself (`0`, its own process group, holds only itself).
pub fn child_program(pid: i32) -> CoreResult<BpfProgram> {
    let own = u64::from(pid.unsigned_abs());
    let not_self = || arg(0, SeccompCmpArgLen::Dword, SeccompCmpOp::Ne, own);
    let mut rules: BTreeMap<i64, Vec<SeccompRule>> = FORKS
        .iter()
        .chain(&[
            libc::SYS_execve,
            libc::SYS_execveat,
            libc::SYS_tkill,
            libc::SYS_setsid,
            libc::SYS_setpgid,
            libc::SYS_pidfd_open,
            libc::SYS_pidfd_send_signal,
            libc::SYS_pidfd_getfd,
        ])
        .map(|&call| (call, Vec::new()))
        .collect();
    rules.insert(
        libc::SYS_clone,
        vec![when(vec![arg(
            0,
            SeccompCmpArgLen::Qword,
            SeccompCmpOp::MaskedEq(libc::CLONE_THREAD as u64),
            0,
        )?])?],
    );
    rules.insert(
        libc::SYS_kill,
        vec![when(vec![
            not_self()?,
            arg(0, SeccompCmpArgLen::Dword, SeccompCmpOp::Ne, 0)?,
        ])?],
    );
    for call in [
        libc::SYS_tgkill,
        libc::SYS_rt_sigqueueinfo,
        libc::SYS_rt_tgsigqueueinfo,
    ] {
        rules.insert(call, vec![when(vec![not_self()?])?]);
    }
    compile(
        rules,
        SeccompAction::Allow,
        SeccompAction::Errno(libc::EPERM as u32),
    )
}

/// A program as the kernel (and bubblewrap's `--seccomp FD`) reads it: `struct sock_filter`
/// records in native byte order.
pub fn program_bytes(program: &BpfProgram) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(program.len() * 8);
    for instruction in program {
        bytes.extend_from_slice(&instruction.code.to_ne_bytes());
        bytes.push(instruction.jt);
        bytes.push(instruction.jf);
        bytes.extend_from_slice(&instruction.k.to_ne_bytes());
    }
    bytes
}

/// What [`confine_child`] achieved, for the run's record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Confinement {
    /// `"enforced"`, `"partly enforced"` (an older kernel's subset) or `"unavailable"`.
    pub landlock: &'static str,
    /// The seccomp programs this call loaded (on top of any loaded before).
    pub seccomp: Vec<&'static str>,
}

/// Restricts the calling process (single-threaded, just forked) for good.
///
/// Landlock, where the kernel has it: `readable` hierarchies may be read, `writable` ones
/// written as well, nothing else; no signals to and no abstract UNIX sockets of processes
/// outside this domain. Then the seccomp programs: the base allow-list and its fallbacks
/// when `with_base` (a process that bubblewrap did not start has neither yet), and always
/// [`child_program`] for `pid`. Both set `no_new_privs` first.
pub fn confine_child(
    pid: i32,
    readable: &[PathBuf],
    writable: &[PathBuf],
    with_base: bool,
) -> CoreResult<Confinement> {
    let landlock_error =
        |error: landlock::RulesetError| CoreError::InvalidArgument(format!("landlock: {error}"));
    let status = Ruleset::default()
        .handle_access(AccessFs::from_all(LANDLOCK_ABI))
        .map_err(landlock_error)?
        .scope(Scope::from_all(LANDLOCK_ABI))
        .map_err(landlock_error)?
        .create()
        .map_err(landlock_error)?
        .add_rules(path_beneath_rules(
            readable,
            AccessFs::from_read(LANDLOCK_ABI),
        ))
        .map_err(landlock_error)?
        .add_rules(path_beneath_rules(
            writable,
            AccessFs::from_all(LANDLOCK_ABI),
        ))
        .map_err(landlock_error)?
        .restrict_self()
        .map_err(landlock_error)?;
    let landlock = match status.ruleset {
        RulesetStatus::FullyEnforced => "enforced",
        RulesetStatus::PartiallyEnforced => "partly enforced",
        RulesetStatus::NotEnforced => "unavailable",
    };
    let mut loaded = Vec::new();
    let mut programs = Vec::new();
    if with_base {
        programs.push(("base", base_program()?));
        programs.push(("fallbacks", fallback_program()?));
    }
    programs.push(("child", child_program(pid)?));
    for (name, program) in &programs {
        seccompiler::apply_filter(program).map_err(seccomp_error)?;
        loaded.push(*name);
    }
    Ok(Confinement {
        landlock,
        seccomp: loaded,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn programs_compile_to_whole_instructions() {
        for program in [
            base_program().unwrap_or_default(),
            fallback_program().unwrap_or_default(),
            child_program(2).unwrap_or_default(),
        ] {
            assert!(!program.is_empty());
            assert_eq!(program_bytes(&program).len(), program.len() * 8);
        }
    }

    #[test]
    fn the_base_list_names_no_call_that_reaches_outside_the_sandbox() {
        let rules = base_rules().unwrap_or_default();
        for call in [
            libc::SYS_ptrace,
            libc::SYS_process_vm_readv,
            libc::SYS_process_vm_writev,
            libc::SYS_mount,
            libc::SYS_umount2,
            libc::SYS_unshare,
            libc::SYS_setns,
            libc::SYS_pivot_root,
            libc::SYS_chroot,
            libc::SYS_keyctl,
            libc::SYS_add_key,
            libc::SYS_request_key,
            libc::SYS_bpf,
            libc::SYS_perf_event_open,
            libc::SYS_userfaultfd,
            libc::SYS_io_uring_setup,
            libc::SYS_open_by_handle_at,
            libc::SYS_init_module,
            libc::SYS_finit_module,
            libc::SYS_kexec_load,
            libc::SYS_reboot,
            libc::SYS_sethostname,
            libc::SYS_clock_settime,
            libc::SYS_fsopen,
            libc::SYS_move_mount,
            libc::SYS_open_tree,
            libc::SYS_mknodat,
        ] {
            assert!(!rules.contains_key(&call), "system call {call} is allowed");
        }
        assert!(rules.contains_key(&libc::SYS_socket));
    }
}
