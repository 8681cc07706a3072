# Sourced by scripts/run and scripts/test: makes sure a fresh Debian machine has what the build
# needs, installing it when it can (as root with apt-get; the Rust toolchain into ~/.cargo, as
# rustup does, for any user). Each step is skipped when its tool is already there.

# The oldest Rust the locked crates accept (ordered-float 5.5.1, under wgpu-hal, asks 1.90).
PENETRATE_MIN_RUST=1.90

setup_fail() {
    echo "$0: $*" >&2
    exit 2
}

# apt-get install the given Debian packages, or stop saying which to install.
setup_apt() {
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "$0: installing $* with apt-get" >&2
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null ||
            setup_fail "apt-get install $* failed"
    else
        setup_fail "missing: install the Debian packages $* (as root: apt-get install $*) and run again"
    fi
}

# True when `cargo` on PATH is at least PENETRATE_MIN_RUST.
setup_cargo_recent() {
    local version
    version=$(cargo --version 2>/dev/null | awk '{print $2}') || return 1
    [ -n "$version" ] || return 1
    [ "$(printf '%s\n%s\n' "$PENETRATE_MIN_RUST" "$version" | sort -V | head -n 1)" = "$PENETRATE_MIN_RUST" ]
}

setup_rust() {
    local cargo_home="${CARGO_HOME:-$HOME/.cargo}"
    if setup_cargo_recent; then
        return
    fi
    # A rustup installed earlier (by this script or by hand) but not on PATH.
    if [ -x "$cargo_home/bin/cargo" ]; then
        export PATH="$cargo_home/bin:$PATH"
        setup_cargo_recent && return
    fi
    if command -v rustup >/dev/null 2>&1; then
        echo "$0: Rust older than $PENETRATE_MIN_RUST; installing the stable toolchain with rustup" >&2
        rustup toolchain install stable --profile minimal || setup_fail "rustup could not install the stable toolchain"
        export RUSTUP_TOOLCHAIN=stable
    else
        echo "$0: no Rust $PENETRATE_MIN_RUST or newer; installing rustup and the stable toolchain into $cargo_home" >&2
        command -v curl >/dev/null 2>&1 || setup_apt curl ca-certificates
        local arch dir init
        arch=$(uname -m)
        dir=$(mktemp -d)
        init="$dir/rustup-init" # rustup-init acts on the name it is called by
        curl --proto '=https' --tlsv1.2 -sSf \
            "https://static.rust-lang.org/rustup/dist/${arch}-unknown-linux-gnu/rustup-init" -o "$init" ||
            setup_fail "could not download rustup-init from static.rust-lang.org"
        chmod +x "$init"
        "$init" -y --profile minimal --default-toolchain stable --no-modify-path ||
            setup_fail "rustup-init failed"
        rm -rf "$dir"
        export PATH="$cargo_home/bin:$PATH"
    fi
    setup_cargo_recent || setup_fail "cargo is still older than $PENETRATE_MIN_RUST after installing: $(cargo --version 2>&1)"
}

# Rust, and the C linker its build needs.
setup_build_tools() {
    command -v cc >/dev/null 2>&1 || setup_apt build-essential
    setup_rust
}

# A Vulkan driver for the GPU tests: on a machine without a GPU, Mesa's software adapter
# lavapipe (gpu-notes.md: without it wgpu falls back to a GL adapter that lacks what the solver
# needs). Without one the GPU tests fail, saying how to get an adapter.
setup_vulkan() {
    if ! ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1; then
        if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
            setup_apt mesa-vulkan-drivers libvulkan1
        else
            echo "$0: no Vulkan driver found; the GPU tests will fail. Install mesa-vulkan-drivers (as root: apt-get install mesa-vulkan-drivers)." >&2
        fi
    fi
}

