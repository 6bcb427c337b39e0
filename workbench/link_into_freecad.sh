#!/bin/sh
# Link the StripWeave workbench into FreeCAD's user Mod folder:
#     <Mod>/StripWeave -> <repo>
# the layout the Addon Manager makes (it clones the repository there): FreeCAD
# reads <repo>/package.xml, whose workbench lives in the subdirectory
# workbench/ (put on sys.path; it holds the namespace package freecad/stripweave_wb).
# <Mod> is $FREECAD_USER_HOME/Mod when FREECAD_USER_HOME is set (FreeCAD then
# uses that folder as its user data folder), else ~/.local/share/FreeCAD/Mod
# (FreeCAD 0.20 on Linux).  Idempotent: re-running it changes nothing, a stale
# link is replaced, and a real folder of the same name is left alone (error).
#
#     sh workbench/link_into_freecad.sh            # link
#     sh workbench/link_into_freecad.sh --remove   # unlink
#
# The workbench adds <repo>/build to sys.path itself, so build the native
# library first (bash .ci/setup).
set -eu

here=$(cd "$(dirname "$0")/.." && pwd -P)
if [ -n "${FREECAD_USER_HOME:-}" ]; then
    mod_dir="$FREECAD_USER_HOME/Mod"
else
    mod_dir="${XDG_DATA_HOME:-$HOME/.local/share}/FreeCAD/Mod"
fi
link="$mod_dir/StripWeave"

if [ "${1:-}" = "--remove" ]; then
    if [ -L "$link" ]; then
        rm "$link"
        echo "removed $link"
    else
        echo "nothing to remove: $link is not a symlink"
    fi
    exit 0
fi

if [ -L "$link" ]; then
    current=$(readlink "$link")
    if [ "$current" = "$here" ]; then
        echo "already linked: $link -> $here"
        exit 0
    fi
    rm "$link"
    echo "replacing stale link $link -> $current"
elif [ -e "$link" ]; then
    echo "error: $link exists and is not a symlink; move it away first" >&2
    exit 1
fi

mkdir -p "$mod_dir"
ln -s "$here" "$link"
echo "linked $link -> $here"
echo "start FreeCAD and pick the StripWeave workbench (the native build must exist in $here/build: bash $here/.ci/setup)"
