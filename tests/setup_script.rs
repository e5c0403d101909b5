//! `scripts/setup` derives the bookworm-backports entry it adds from the machine's own apt
//! sources (the archive address and keyring of its Debian entry). Here on copies of typical
//! sources in a temporary apt folder (`PASSGRAPH_APT_DIR`), through `--backports-entry`, which
//! prints the entry and changes nothing; and what it decides to install, through `--dry-run`
//! with a stand-in `dpkg-query` and release (`PASSGRAPH_OS_RELEASE`).

mod common;

use common::root;
use std::process::Command;

/// Runs `scripts/setup --backports-entry bookworm` on an apt folder holding `files`.
fn backports_entry(files: &[(&str, &str)]) -> (bool, String, String) {
    let apt = tempfile::tempdir().unwrap();
    std::fs::create_dir(apt.path().join("sources.list.d")).unwrap();
    for (name, text) in files {
        std::fs::write(apt.path().join(name), text).unwrap();
    }
    let out = Command::new("bash")
        .arg(root().join("scripts/setup"))
        .args(["--backports-entry", "bookworm"])
        .env("PASSGRAPH_APT_DIR", apt.path())
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// The entry's fields, comments left out.
fn fields(entry: &str) -> Vec<&str> {
    entry.lines().filter(|l| !l.starts_with('#')).collect()
}

const DEBIAN_SOURCES: &str = "\
Types: deb
# http://snapshot.debian.org/archive/debian/20250520T000000Z
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
";

#[test]
fn deb822_sources_of_a_debian_12_image_give_the_same_archive_and_keyring() {
    let (ok, out, err) = backports_entry(&[("sources.list.d/debian.sources", DEBIAN_SOURCES)]);
    assert!(ok, "{err}");
    assert_eq!(
        fields(&out),
        [
            "Types: deb",
            "URIs: http://deb.debian.org/debian",
            "Suites: bookworm-backports",
            "Components: main",
            "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg",
        ]
    );
    assert!(out.contains("debian.sources"), "names its source:\n{out}");
}

#[test]
fn one_line_sources_with_options_and_a_third_party_bookworm_suite_first() {
    let list = "\
# deb cdrom:[Debian GNU/Linux 12]/ bookworm main
deb [signed-by=/etc/apt/keyrings/docker.gpg] https://download.docker.com/linux/debian bookworm stable
deb [ arch=amd64 signed-by=/usr/share/keyrings/debian-archive-keyring.gpg ] http://ftp.fr.debian.org/debian/ bookworm main contrib non-free-firmware
deb-src http://ftp.fr.debian.org/debian/ bookworm main
deb http://security.debian.org/debian-security bookworm-security main
";
    let (ok, out, err) = backports_entry(&[("sources.list", list)]);
    assert!(ok, "{err}");
    assert_eq!(
        fields(&out),
        [
            "Types: deb",
            "URIs: http://ftp.fr.debian.org/debian/",
            "Suites: bookworm-backports",
            "Components: main",
            "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg",
        ]
    );
}

#[test]
fn an_entry_without_a_keyring_gives_one_without_signed_by() {
    let (ok, out, err) = backports_entry(&[(
        "sources.list",
        "deb http://mirror.example.org/debian bookworm main\n",
    )]);
    assert!(ok, "{err}");
    assert_eq!(
        fields(&out),
        [
            "Types: deb",
            "URIs: http://mirror.example.org/debian",
            "Suites: bookworm-backports",
            "Components: main",
        ]
    );
}

#[test]
fn a_mirror_list_uri_and_an_inline_key_are_copied_as_they_are() {
    let sources = "\
Types: deb deb-src
URIs: mirror+file:///etc/apt/mirrors/debian.list
Suites: bookworm bookworm-updates
Components: main
Signed-By:
 -----BEGIN PGP PUBLIC KEY BLOCK-----
 .
 mQINBGPL0BUBEADmW5NdOOHwPIJlgPu6JDcKw/NZJPR8lsD3K87ZM18gzyQZJD+w
 -----END PGP PUBLIC KEY BLOCK-----
";
    let (ok, out, err) = backports_entry(&[("sources.list.d/debian.sources", sources)]);
    assert!(ok, "{err}");
    assert_eq!(
        fields(&out),
        [
            "Types: deb",
            "URIs: mirror+file:///etc/apt/mirrors/debian.list",
            "Suites: bookworm-backports",
            "Components: main",
            "Signed-By: ",
            " -----BEGIN PGP PUBLIC KEY BLOCK-----",
            " .",
            " mQINBGPL0BUBEADmW5NdOOHwPIJlgPu6JDcKw/NZJPR8lsD3K87ZM18gzyQZJD+w",
            " -----END PGP PUBLIC KEY BLOCK-----",
        ]
    );
}

#[test]
fn an_existing_backports_entry_adds_nothing_but_a_disabled_one_does_not_count() {
    let existing = "deb http://deb.debian.org/debian bookworm-backports main\n";
    let (ok, out, err) = backports_entry(&[
        ("sources.list.d/debian.sources", DEBIAN_SOURCES),
        ("sources.list.d/backports.list", existing),
    ]);
    assert!(ok, "{err}");
    assert_eq!(out, "");

    let disabled = "\
Enabled: no
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm-backports
Components: main
";
    let (ok, out, err) = backports_entry(&[
        ("sources.list.d/debian.sources", DEBIAN_SOURCES),
        ("sources.list.d/backports.sources", disabled),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("Suites: bookworm-backports"), "{out}");
}

#[test]
fn no_debian_entry_is_an_error_naming_the_apt_folder() {
    let (ok, out, err) = backports_entry(&[(
        "sources.list.d/other.list",
        "deb https://download.docker.com/linux/debian bookworm stable\n",
    )]);
    assert!(!ok);
    assert_eq!(out, "");
    assert!(
        err.contains("no 'bookworm' Debian entry") && err.contains("sources.list.d"),
        "{err}"
    );
}

#[test]
fn an_unknown_argument_is_a_usage_error() {
    let out = Command::new("bash")
        .arg(root().join("scripts/setup"))
        .arg("--frobnicate")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("unknown argument '--frobnicate'"), "{err}");
}

/// The README's first block is two commands, each setting up first, and CI runs the same
/// set-up and the README's test command as written there.
#[test]
fn readme_and_ci_run_the_same_setup_and_test_command() {
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let block = readme
        .split("```sh\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("README.md should open with a sh block");
    let commands: Vec<&str> = block
        .lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(
        commands,
        [
            "scripts/setup && cargo run --release",
            "scripts/setup && cargo test"
        ]
    );
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let ci_lines: Vec<&str> = ci.lines().map(str::trim).collect();
    assert!(ci_lines.contains(&"scripts/setup"), "{ci}");
    assert!(ci_lines.contains(&commands[1]), "{ci}");
    assert!(
        ci_lines.contains(&"cargo clippy --all-targets --locked -- -D warnings"),
        "{ci}"
    );
}

/// Every package the set-up looks for, as `dpkg-query` lists it when installed.
const ALL_PRESENT: [(&str, &str); 9] = [
    ("mesa-vulkan-drivers:amd64", "25.0.7-2~bpo12+1"),
    ("fonts-dejavu-core", "2.37-6"),
    ("xvfb", "2:21.1.7-3+deb12u13"),
    ("libx11-6:amd64", "2:1.8.4-2+deb12u2"),
    ("libx11-xcb1:amd64", "2:1.8.4-2+deb12u2"),
    ("libxcursor1:amd64", "1:1.2.1-1"),
    ("libxi6:amd64", "2:1.8-1+b1"),
    ("libxkbcommon-x11-0:amd64", "1.5.0-1"),
    ("graphviz", "2.42.2-7+deb12u1"),
];

/// A machine for `scripts/setup`: release `codename`, `installed` packages (a stand-in
/// `dpkg-query` lists them), the apt `sources`, and stand-ins for `apt-get` (it logs its
/// arguments and exits with `apt_exit`) and `sudo`.
struct Machine {
    dir: tempfile::TempDir,
}

impl Machine {
    fn new(
        codename: &str,
        installed: &[(&str, &str)],
        sources: &[(&str, &str)],
        apt_exit: i32,
    ) -> Machine {
        let dir = tempfile::tempdir().unwrap();
        let bin = dir.path().join("bin");
        std::fs::create_dir(&bin).unwrap();
        let listing: String = installed
            .iter()
            .map(|(name, version)| format!("{name} ii  {version}\n"))
            .collect();
        let log = dir.path().join("apt-get.log");
        for (name, script) in [
            (
                "dpkg-query",
                format!("#!/bin/sh\ncat <<'END'\n{listing}END\n"),
            ),
            (
                "apt-get",
                format!(
                    "#!/bin/sh\necho \"$*\" >> '{}'\nexit {apt_exit}\n",
                    log.display()
                ),
            ),
            ("sudo", "#!/bin/sh\nexec \"$@\"\n".to_string()),
        ] {
            let path = bin.join(name);
            std::fs::write(&path, script).unwrap();
            let mut permissions = std::fs::metadata(&path).unwrap().permissions();
            std::os::unix::fs::PermissionsExt::set_mode(&mut permissions, 0o755);
            std::fs::set_permissions(&path, permissions).unwrap();
        }
        let apt = dir.path().join("apt");
        std::fs::create_dir_all(apt.join("sources.list.d")).unwrap();
        for (name, text) in sources {
            std::fs::write(apt.join(name), text).unwrap();
        }
        std::fs::write(
            dir.path().join("os-release"),
            format!("ID=debian\nVERSION_CODENAME={codename}\n"),
        )
        .unwrap();
        Machine { dir }
    }

    /// Runs `scripts/setup` with `args`: success, and stdout then stderr with the apt folder
    /// written as APT.
    fn setup(&self, args: &[&str]) -> (bool, String) {
        let d = self.dir.path();
        let path = std::env::join_paths(
            std::iter::once(d.join("bin"))
                .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap())),
        )
        .unwrap();
        let out = Command::new("bash")
            .arg(root().join("scripts/setup"))
            .args(args)
            .env("PATH", path)
            .env("PASSGRAPH_APT_DIR", d.join("apt"))
            .env("PASSGRAPH_OS_RELEASE", d.join("os-release"))
            .output()
            .unwrap();
        let text = String::from_utf8(out.stdout).unwrap() + &String::from_utf8(out.stderr).unwrap();
        (
            out.status.success(),
            text.replace(d.join("apt").to_str().unwrap(), "APT"),
        )
    }

    /// What the stand-in apt-get was asked to do, one call a line.
    fn apt_calls(&self) -> String {
        std::fs::read_to_string(self.dir.path().join("apt-get.log")).unwrap_or_default()
    }

    /// A stand-in `cargo` whose `cargo install --list` prints `listing`.
    fn with_cargo_installed(self, listing: &str) -> Machine {
        let path = self.dir.path().join("bin/cargo");
        std::fs::write(
            &path,
            format!("#!/bin/sh\n[ \"$1 $2\" = \"install --list\" ] || exit 1\ncat <<'END'\n{listing}END\n"),
        )
        .unwrap();
        let mut permissions = std::fs::metadata(&path).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut permissions, 0o755);
        std::fs::set_permissions(&path, permissions).unwrap();
        self
    }

    fn added_entry(&self) -> Option<String> {
        let path = self
            .dir
            .path()
            .join("apt/sources.list.d/passgraph-backports.sources");
        std::fs::read_to_string(path).ok()
    }
}

/// `scripts/setup --dry-run` on a [`Machine`]: what it would write and run.
fn dry_run(codename: &str, installed: &[(&str, &str)], sources: &[(&str, &str)]) -> String {
    let machine = Machine::new(codename, installed, sources, 0);
    let (ok, out) = machine.setup(&["--dry-run"]);
    assert!(ok, "{out}");
    assert_eq!(machine.apt_calls(), "", "a dry run runs no apt-get");
    out
}

#[test]
fn with_everything_present_it_runs_no_apt_at_all() {
    let out = dry_run(
        "bookworm",
        &ALL_PRESENT,
        &[("sources.list.d/debian.sources", DEBIAN_SOURCES)],
    );
    assert_eq!(
        out,
        "setup: nothing to install (mesa-vulkan-drivers 25.0.7-2~bpo12+1)\n"
    );
}

#[test]
fn bookworms_own_mesa_is_upgraded_from_a_backports_entry_it_adds() {
    let mut installed = ALL_PRESENT;
    installed[0].1 = "22.3.6-1+deb12u2";
    let out = dry_run(
        "bookworm",
        &installed,
        &[("sources.list.d/debian.sources", DEBIAN_SOURCES)],
    );
    let apt = "env DEBIAN_FRONTEND=noninteractive apt-get";
    for part in [
        "would write APT/sources.list.d/passgraph-backports.sources:\n",
        "URIs: http://deb.debian.org/debian\nSuites: bookworm-backports\n",
        &format!("would run: {apt} update -qq\n"),
        &format!(
            "would run: {apt} install -y -qq --no-install-recommends -t bookworm-backports mesa-vulkan-drivers\n"
        ),
    ] {
        assert!(out.contains(part), "{part:?} missing from:\n{out}");
    }
    assert_eq!(out.matches(" install ").count(), 1, "only Mesa:\n{out}");
}

#[test]
fn a_fresh_bookworm_gets_mesa_from_backports_and_the_rest_from_its_release() {
    let out = dry_run(
        "bookworm",
        &[],
        &[
            ("sources.list.d/debian.sources", DEBIAN_SOURCES),
            (
                "sources.list.d/backports.list",
                "deb http://deb.debian.org/debian bookworm-backports main\n",
            ),
        ],
    );
    assert!(!out.contains("would write"), "backports is there:\n{out}");
    assert!(
        out.contains("-t bookworm-backports mesa-vulkan-drivers\n")
            && out.contains(
                "install -y -qq --no-install-recommends fonts-dejavu-core xvfb libx11-6 libx11-xcb1 libxcursor1 libxi6 libxkbcommon-x11-0 graphviz"
            ),
        "{out}"
    );
}

#[test]
fn a_newer_release_takes_mesa_from_its_own_suite() {
    let out = dry_run("trixie", &ALL_PRESENT[1..], &[]);
    assert!(
        out.contains("install -y -qq --no-install-recommends mesa-vulkan-drivers\n"),
        "{out}"
    );
    assert!(!out.contains("backports"), "{out}");
}

#[test]
fn an_unreachable_archive_keeps_bookworms_mesa_with_a_warning() {
    let mut installed = ALL_PRESENT;
    installed[0].1 = "22.3.6-1+deb12u2";
    let sources = [("sources.list.d/debian.sources", DEBIAN_SOURCES)];
    let machine = Machine::new("bookworm", &installed, &sources, 100);
    let (ok, out) = machine.setup(&[]);
    assert!(ok, "Mesa 22.3.6 works, only slower:\n{out}");
    assert!(
        out.contains("warning: apt-get update failed (after adding APT/sources.list.d/passgraph-backports.sources); keeping mesa-vulkan-drivers 22.3.6-1+deb12u2"),
        "{out}"
    );
    assert!(
        machine
            .added_entry()
            .is_some_and(|e| e.contains("Suites: bookworm-backports\n")),
        "{out}"
    );
    assert_eq!(machine.apt_calls(), "update -qq\n");
    // The entry is there now: a second run does not add it again.
    let (ok, out) = machine.setup(&[]);
    assert!(ok && !out.contains("adding"), "{out}");
}

#[test]
fn a_missing_package_that_cannot_be_installed_is_an_error_naming_it() {
    let machine = Machine::new(
        "bookworm",
        &ALL_PRESENT[..2],
        &[("sources.list.d/debian.sources", DEBIAN_SOURCES)],
        100,
    );
    let (ok, out) = machine.setup(&[]);
    assert!(!ok, "{out}");
    assert!(
        out.contains("setup: error: apt-get update failed; still missing: xvfb libx11-6"),
        "{out}"
    );
}

#[test]
fn it_installs_what_is_missing_through_apt_get() {
    let machine = Machine::new(
        "bookworm",
        &ALL_PRESENT[..7],
        &[("sources.list.d/debian.sources", DEBIAN_SOURCES)],
        0,
    );
    let (ok, out) = machine.setup(&[]);
    assert!(ok, "{out}");
    assert_eq!(
        machine.apt_calls(),
        "update -qq\ninstall -y -qq --no-install-recommends libxkbcommon-x11-0 graphviz\n"
    );
    assert_eq!(machine.added_entry(), None, "Mesa 25 is there");
}

/// What `--jobs` adds: Slurm, munge and Python's yaml (apt), openjd-cli 0.1.18 (cargo).
const JOBS_PACKAGES: [(&str, &str); 5] = [
    ("slurmctld", "22.05.8-4+deb12u3"),
    ("slurmd", "22.05.8-4+deb12u3"),
    ("slurm-client", "22.05.8-4+deb12u3"),
    ("munge", "0.5.15-2+deb12u1"),
    ("python3-yaml", "6.0-3+b2"),
];
const OPENJD_LISTED: &str = "openjd-cli v0.1.18:\n    openjd\n";
const OPENJD_INSTALL: &str = "would run: cargo install --locked openjd-cli --version 0.1.18\n";

#[test]
fn with_jobs_it_adds_slurm_munge_yaml_and_the_pinned_openjd() {
    let sources = [("sources.list.d/debian.sources", DEBIAN_SOURCES)];
    // An older openjd-cli does not count.
    let machine = Machine::new("bookworm", &ALL_PRESENT, &sources, 0)
        .with_cargo_installed("openjd-cli v0.1.20:\n    openjd\n");
    let (ok, out) = machine.setup(&["--dry-run", "--jobs"]);
    assert!(ok, "{out}");
    assert!(
        out.contains(
            "install -y -qq --no-install-recommends slurmctld slurmd slurm-client munge python3-yaml\n"
        ) && out.ends_with(OPENJD_INSTALL),
        "{out}"
    );
    // Without --jobs none of it.
    let (ok, out) = machine.setup(&["--dry-run"]);
    assert!(ok, "{out}");
    assert_eq!(
        out,
        "setup: nothing to install (mesa-vulkan-drivers 25.0.7-2~bpo12+1)\n"
    );
}

#[test]
fn with_jobs_and_only_openjd_missing_it_runs_no_apt() {
    let installed: Vec<_> = ALL_PRESENT.iter().chain(&JOBS_PACKAGES).copied().collect();
    let sources = [("sources.list.d/debian.sources", DEBIAN_SOURCES)];
    let machine = Machine::new("bookworm", &installed, &sources, 0).with_cargo_installed("");
    let (ok, out) = machine.setup(&["--jobs", "--dry-run"]);
    assert!(ok, "{out}");
    assert_eq!(out, OPENJD_INSTALL);
}

#[test]
fn with_jobs_and_everything_present_there_is_nothing_to_install() {
    let installed: Vec<_> = ALL_PRESENT.iter().chain(&JOBS_PACKAGES).copied().collect();
    let sources = [("sources.list.d/debian.sources", DEBIAN_SOURCES)];
    let machine =
        Machine::new("bookworm", &installed, &sources, 0).with_cargo_installed(OPENJD_LISTED);
    let (ok, out) = machine.setup(&["--jobs"]);
    assert!(ok, "{out}");
    assert_eq!(
        out,
        "setup: nothing to install (mesa-vulkan-drivers 25.0.7-2~bpo12+1, openjd-cli 0.1.18)\n"
    );
    assert_eq!(machine.apt_calls(), "");
}

/// CI sets up for and runs the job definitions under jobs/ after the tests.
#[test]
fn ci_runs_the_job_definitions_after_the_tests() {
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let lines: Vec<&str> = ci.lines().map(str::trim).collect();
    let at = |line: &str| lines.iter().position(|l| *l == line);
    let (Some(test), Some(setup), Some(jobs)) = (
        at("scripts/setup && cargo test"),
        at("scripts/setup --jobs"),
        at("jobs/test"),
    ) else {
        panic!("{ci}");
    };
    assert!(test < setup && setup < jobs, "{ci}");
}
