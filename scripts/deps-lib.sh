# shellcheck shell=sh
# Helpers shared by the install scripts (sourced by install-deps.sh and
# install-cross-deps.sh; POSIX sh). Each install script declares what it
# promises with deps_need_* after installing, and ends with deps_verify, which
# fails naming every missing piece: a package list that forgets something is
# caught on the next run on a fresh machine instead of by a later build error.
#
# The caller sets deps_name (the prefix of every message) before sourcing.

: "${deps_name:=install}"
deps_sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    deps_sudo="sudo"
  else
    echo "${deps_name}: not root and no sudo: run this as root (it installs Debian packages with apt-get)" >&2
    exit 1
  fi
fi
deps_apt="$deps_sudo env DEBIAN_FRONTEND=noninteractive apt-get -q -o DPkg::Lock::Timeout=600"
deps_updated=0
deps_problems=""
deps_checked=0

# apt-get update once per run. A partial failure (one index of one suite) is
# reported and tolerated: the installs below fail loudly if what they need is
# really unreachable, and deps_verify names what is missing.
deps_apt_update() {
  [ "$deps_updated" -eq 1 ] && return 0
  deps_updated=1
  # shellcheck disable=SC2086
  if ! $deps_apt update; then
    echo "${deps_name}: warning: apt-get update reported errors (see above); continuing with the indexes that did download" >&2
  fi
}

# The packages of "$@" that dpkg does not list as installed.
deps_missing_pkgs() {
  _missing=""
  for _p in "$@"; do
    dpkg-query -W -f='${Status}' "$_p" 2>/dev/null | grep -q "install ok installed" || _missing="$_missing $_p"
  done
  echo "$_missing"
}

# Installs the packages of "$@" that are missing (no recommends).
deps_install() {
  # shellcheck disable=SC2086
  _todo=$(deps_missing_pkgs "$@")
  if [ -n "$_todo" ]; then
    echo "${deps_name}: installing:$_todo"
    deps_apt_update
    # shellcheck disable=SC2086
    $deps_apt install -y --no-install-recommends $_todo
  else
    echo "${deps_name}: already installed: $*"
  fi
}

deps_problem() {
  deps_problems="${deps_problems}
  - $1"
}

# deps_need_cmd COMMAND WHAT: COMMAND must be on PATH.
deps_need_cmd() {
  deps_checked=$((deps_checked + 1))
  command -v "$1" >/dev/null 2>&1 || deps_problem "command '$1' ($2)"
}

# deps_need_file PATH WHAT: PATH must exist.
deps_need_file() {
  deps_checked=$((deps_checked + 1))
  [ -e "$1" ] || deps_problem "file $1 ($2)"
}

# deps_need_pkg PACKAGE...: each must be installed according to dpkg.
deps_need_pkg() {
  for _p in "$@"; do
    deps_checked=$((deps_checked + 1))
    dpkg-query -W -f='${Status}' "$_p" 2>/dev/null | grep -q "install ok installed" ||
      deps_problem "Debian package $_p"
  done
}

# Ends the script's checks: exit 1 naming everything missing, or one line of counts.
deps_verify() {
  if [ -n "$deps_problems" ]; then
    echo "${deps_name}: FAILED: after the install these are still missing:${deps_problems}" >&2
    exit 1
  fi
  echo "${deps_name}: checked $deps_checked promised items ($1): all present"
}
