#!/usr/bin/env bash
# Installs the Debian packages named on the command line (the setup scripts pass those that are
# missing), without questions, as root or with sudo.
set -euo pipefail
[ "$#" -gt 0 ] || exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "$@" >/dev/null
