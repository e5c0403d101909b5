//! `scripts/setup` derives the bookworm-backports entry it adds from the machine's own apt
//! sources (the archive address and keyring of its Debian entry). Here on copies of typical
//! sources in a temporary apt folder (`PASSGRAPH_APT_DIR`), through `--backports-entry`, which
//! prints the entry and changes nothing.

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
