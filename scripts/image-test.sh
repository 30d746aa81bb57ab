#!/bin/sh
# `make image-test` (opt-in, slow: minutes): the container image (Containerfile) built and run with
# no container registry. Its Debian bookworm base is made here by mmdebstrap from Debian's packages and
# imported into podman; the image is built on it with podman (buildah) and started; its lab must answer
# /health with the loop alive, as the user jovyan. Root only (rootful podman). The base is kept in
# $IMAGE_TEST_DIR (made once: ~3 min); the build reuses podman's layer cache.
#
# Podman on a machine like the project's (a VM with cgroups v1 + a v2 hierarchy holding hugetlb, and
# rlimits that even root cannot raise) needs: runc (crun refuses cgroups "hybrid mode"), the rlimits
# at most the current hard ones (podman asks for 1048576 open files by default: refused; processes:
# 30,000 taken, 40,000 refused though the hard limit is 96,367), vfs storage,
# `--isolation chroot` for the build's RUN steps and the host's network (the test reaches the lab on
# 127.0.0.1 only). A laptop's Docker or Podman needs none of this: docs/hosting-image.md.
set -eu
cd "$(dirname "$0")/.."
DIR=${IMAGE_TEST_DIR:-${TMPDIR:-/tmp}/hri-lab-image-test}
IMAGE=localhost/hri-lab:test
BASE=localhost/hri-lab-bookworm-base:test
PORT=${IMAGE_TEST_PORT:-18765}
NAME=hri-lab-image-test-$$
PODMAN="podman --storage-driver vfs --runtime runc"
LIMITS="--ulimit nofile=$(ulimit -Hn):$(ulimit -Hn) --ulimit nproc=16384:16384"
[ "$(id -u)" = 0 ] || { echo "image-test: needs root (rootful podman)" >&2; exit 2; }
command -v podman >/dev/null && command -v mmdebstrap >/dev/null && command -v runc >/dev/null || {
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq podman buildah mmdebstrap runc >/dev/null
}
mkdir -p "$DIR"
started=$(date +%s)

if ! $PODMAN image exists $BASE; then
    [ -f "$DIR/bookworm.tar" ] || mmdebstrap --quiet --variant=minbase bookworm "$DIR/bookworm.tar"
    $PODMAN import --quiet "$DIR/bookworm.tar" $BASE >/dev/null
fi
echo "image-test: base ready after $(( $(date +%s) - started )) s"

# a proxy that re-signs TLS (pip's/uv's CA bundle in the environment): the build gets the same bundle
ca=""
for var in PIP_CERT SSL_CERT_FILE; do
    eval "file=\${$var:-}"
    if [ -n "$file" ] && [ -f "$file" ]; then
        ca="$ca --build-arg $var=$file -v $file:$file:ro"
    fi
done
# shellcheck disable=SC2086  # word splitting wanted
$PODMAN build --quiet --isolation chroot --network host $LIMITS $ca --build-arg BASE=$BASE -t $IMAGE -f Containerfile . >/dev/null
echo "image-test: image built after $(( $(date +%s) - started )) s"

# the image's own command, its port moved to a free one on the host's loopback
# shellcheck disable=SC2086
$PODMAN run -d --rm --name $NAME --network host $LIMITS $IMAGE \
    hri-lab serve --host 127.0.0.1 --port "$PORT" --no-token >/dev/null
trap '$PODMAN rm -f -t 5 $NAME >/dev/null 2>&1 || true' EXIT
user=$($PODMAN exec $NAME id -un)
[ "$user" = jovyan ] || { echo "image-test: the lab runs as $user, not jovyan" >&2; exit 1; }
if grep -q '^hub = \[' pyproject.toml; then  # JupyterLab and jupyter-server-proxy: the singleuser image's part
    $PODMAN exec $NAME python -c "import jupyterlab, jupyter_server_proxy" || { echo "image-test: no JupyterLab" >&2; exit 1; }
fi
deadline=$(( $(date +%s) + 300 ))
until curl -fsS "http://127.0.0.1:$PORT/health" 2>/dev/null | grep -q '"loop_alive":true'; do
    if [ "$(date +%s)" -gt "$deadline" ] || ! $PODMAN container exists $NAME; then
        $PODMAN logs $NAME 2>&1 | tail -20 >&2 || true
        echo "image-test: the image's lab did not answer /health" >&2
        exit 1
    fi
    sleep 1
done
echo "image-test: /health answered by the image's lab (user $user) after $(( $(date +%s) - started )) s"
