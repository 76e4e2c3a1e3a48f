# Sourced by scripts/chroot and scripts/fresh-machine: the Debian mirror and the mounts a root file system
# needs to run programs from the host's kernel. Needs root.

# The Debian mirror the host already uses: first `deb` source (one-line .list or deb822 .sources) whose suite
# is a plain release (not -security/-updates/-backports) and whose URI is not a security archive.
# BOUNCE_CHROOT_MIRROR overrides it.
find_mirror() {
    if [[ -n ${BOUNCE_CHROOT_MIRROR:-} ]]; then echo "$BOUNCE_CHROOT_MIRROR"; return; fi
    local files=() f
    [[ -f /etc/apt/sources.list ]] && files+=(/etc/apt/sources.list)
    for f in /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
        [[ -f $f ]] && files+=("$f")
    done
    local uri
    uri=$(awk '
        function ok(u, s) { return u ~ /^(https?|file):/ && u !~ /security/ && s !~ /-(security|updates|backports)/ }
        function flush() {
            if (!found && !disabled && types ~ /[ \t]deb([ \t]|$)/ && ok(uris, suites)) { print uris; found = 1 }
            types = uris = suites = ""; disabled = 0
        }
        FNR == 1 { flush() }
        FILENAME ~ /\.sources$/ {
            if ($0 ~ /^[ \t]*$/) { flush(); next }
            if ($0 ~ /^[ \t]*#/) next
            key = tolower($1)
            if (key == "types:")  types = $0
            if (key == "uris:")   uris = $2
            if (key == "suites:") suites = $2
            if (key == "enabled:" && tolower($2) == "no") disabled = 1
            next
        }
        $1 == "deb" {
            i = 2; if ($i ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
            if (!found && ok($i, $(i + 1))) { print $i; found = 1 }
        }
        END { flush() }
    ' "${files[@]}" | head -n1)
    [[ -n $uri ]] || { echo "no Debian mirror found in the host's apt sources; set BOUNCE_CHROOT_MIRROR" >&2; return 1; }
    echo "${uri%/}"
}

# Mounts under DIR visible in this namespace (deepest first).
mounts_under() {
    awk -v d="$1" '$5 == d || index($5, d "/") == 1 { print $5 }' /proc/self/mountinfo | sort -r
}

unmount_all_under() {
    local m
    for m in $(mounts_under "$1"); do umount -l "$m" 2>/dev/null || true; done
}

# Mount the pseudo file systems into DIR. Called inside a private mount namespace (or with a trap).
mount_system() {
    local dir=$1
    mount -t proc proc "$dir/proc" 2>/dev/null || mount --rbind /proc "$dir/proc"
    mount --rbind /sys "$dir/sys"
    mount --rbind /dev "$dir/dev"   # brings /dev/pts and /dev/shm along
    mount --make-rslave "$dir/sys" "$dir/dev" 2>/dev/null || true
}

# Run "$@" in a private mount namespace so every mount vanishes when it exits, even on a crash and even when
# several runs overlap. Falls back to a plain shell (the caller then traps) with BOUNCE_CHROOT_NO_NS=1.
in_namespace() {
    if unshare -m --propagation private true 2>/dev/null; then
        exec unshare -m --propagation private -- "$@"
    fi
    BOUNCE_CHROOT_NO_NS=1 exec "$@"
}

# Plumbing a minbase root lacks that any installed machine has: name resolution, /etc/mtab (Blender lists
# mounted file systems from it), and no services started by package installs.
prepare_root() {
    local dir=$1
    cp -L /etc/resolv.conf "$dir/etc/resolv.conf" 2>/dev/null || true
    [[ -e $dir/etc/mtab ]] || ln -sf ../proc/self/mounts "$dir/etc/mtab"
    printf '#!/bin/sh\nexit 101\n' >"$dir/usr/sbin/policy-rc.d"
    chmod +x "$dir/usr/sbin/policy-rc.d"
}
