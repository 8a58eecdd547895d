#!/usr/bin/env bash
# Installs what ridge serve's web pages and the headless browser test (tests/browser/run.mjs) need:
# Debian's chromium (the test drives it through playwright-core, WebGL on SwiftShader), Node.js 18+
# with npm, and the pinned npm packages of web/package-lock.json into web/node_modules (served by
# ridge serve as /node_modules/...). Idempotent: re-running only installs what is missing or stale.
# Must run as root (or via sudo).
set -euo pipefail

start=$SECONDS
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SUDO=""
[[ $(id -u) -ne 0 ]] && SUDO="sudo"

packages=(
  chromium                       # headless browser; its dependencies bring the X/GTK/NSS libraries
  fonts-liberation               # some font, so pages lay out text (widgets, attribution) in headless mode
)
# Debian 12's nodejs is 18; only install it when there is no node or an older one (a newer node,
# e.g. from NodeSource, is kept).
node_major=$(node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0)
if ((node_major < 18)) || ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# npm ci wipes and rebuilds node_modules, so it is skipped when the installed tree came from this
# very lock file (a stamp of the lock's hash is written after a successful install).
cd "$root/web"
stamp=node_modules/.ridge-lock.sha256
if [[ -f package-lock.json ]]; then
  lock_hash=$(sha256sum package-lock.json | cut -d' ' -f1)
  if [[ ! -f $stamp || $(cat "$stamp") != "$lock_hash" ]]; then
    npm ci --no-audit --no-fund
    echo "$lock_hash" > "$stamp"
  fi
else
  npm install --no-audit --no-fund
fi

# (stderr: Debian's chromium wrapper script can complain about /dev/shm while printing its version)
echo "ridge: web dependencies present ($(chromium --version 2>/dev/null), node $(node --version)) in $((SECONDS - start)) s"
