#!/bin/sh
# The Debian/Ubuntu packages hri-lab needs beside its venv, by group; apt-get runs only when one is
# missing AND we are root. Otherwise the exact `sudo apt-get install` line is printed and we stop
# (exit 1), or, for an --optional group, go on (exit 0) after saying what is lost without it.
#
#   scripts/system-deps.sh [--check] [--optional GROUP]... GROUP...
#
# Groups (what each is for, and how we tell that it is there):
#   python      python3 with venv and pip (the set-up's venv; the container image)
#   make        GNU make (the set-up's targets; the container image)
#   egl         Mesa's EGL/GL: the camera renders offscreen (llvmpipe without a GPU)
#   openmp      libgomp: the OpenMP runtime the compiled kernels' libraries load
#   bubblewrap  bwrap: students' controllers and graded files run sandboxed
#   chromium    Debian's chromium-headless-shell: the browser tests (playwright drives it; bench/page_responsiveness.py)
#   wrk         the HTTP load generator of `make bench`
#   ros1        Debian's real ROS 1 (roscore, rospy): the tests that hold the lab's emulation to it (bench/ros1_oracle.py)
# --check: only say what is missing (exit 1 if anything required is), never install.
set -eu
PATH="$PATH:/usr/sbin:/sbin"  # ldconfig lives in /sbin, outside a normal user's PATH on Debian

packages() {
    case "$1" in
        python) echo "python3 python3-venv python3-pip" ;;
        make) echo "make" ;;
        egl) echo "libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri" ;;
        openmp) echo "libgomp1" ;;
        bubblewrap) echo "bubblewrap" ;;
        chromium) echo "chromium-headless-shell" ;;
        wrk) echo "wrk" ;;
        ros1) echo "ros-core python3-rospy" ;;
        *) echo "system-deps: unknown group '$1'" >&2; exit 2 ;;
    esac
}

present() {
    case "$1" in
        python) command -v python3 >/dev/null && python3 -c "import ensurepip, venv" 2>/dev/null ;;
        make) command -v make >/dev/null ;;
        egl) ldconfig -p 2>/dev/null | grep -q 'libEGL_mesa.so.0' && ldconfig -p 2>/dev/null | grep -q 'libGL.so.1' ;;
        openmp) ldconfig -p 2>/dev/null | grep -q 'libgomp.so.1' ;;
        bubblewrap) command -v bwrap >/dev/null ;;
        chromium) command -v chromium-headless-shell >/dev/null ;;
        wrk) command -v wrk >/dev/null ;;
        ros1) command -v roscore >/dev/null && /usr/bin/python3 -c 'import rospy' 2>/dev/null ;;
    esac
}

lost() {  # what an --optional group's absence costs
    case "$1" in
        bubblewrap) echo "the lab starts WITHOUT the sandbox: grading (hri-lab grade) and --controller FILE need it" ;;
        *) echo "the $1 group's features are off" ;;
    esac
}

check_only=0
required=""
optional=""
while [ $# -gt 0 ]; do
    case "$1" in
        --check) check_only=1 ;;
        --optional) shift; packages "$1" >/dev/null; optional="$optional $1" ;;
        *) packages "$1" >/dev/null; required="$required $1" ;;
    esac
    shift
done

missing_required=""
missing_optional=""
for group in $required; do present "$group" || missing_required="$missing_required $(packages "$group")"; done
for group in $optional; do present "$group" || missing_optional="$missing_optional $group"; done
[ -z "$missing_required$missing_optional" ] && exit 0

all_packages="$missing_required"
for group in $missing_optional; do all_packages="$all_packages $(packages "$group")"; done
all_packages=$(echo $all_packages)  # one space between names

if [ "$check_only" = 0 ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $all_packages >/dev/null
    exit 0
fi

if ! command -v apt-get >/dev/null; then
    how="this system has no apt-get: install the equivalents of these Debian packages ($all_packages), or use the container image (docs/hosting-image.md)"
else
    how="sudo apt-get install -y $all_packages"
fi
if [ -n "$missing_required" ]; then
    echo "hri-lab needs system packages that are missing. Install them, then run this again:" >&2
    echo "    $how" >&2
    exit 1
fi
for group in $missing_optional; do
    echo "hri-lab: $group is missing ($(lost "$group")). To add it: sudo apt-get install -y $(packages "$group")" >&2
done
exit 0
