#!/usr/bin/env bash
# Regenerates the deck and CalculiX's matrices of the block (block.inp -> block.sti,
# block.mas, block.dof). Without arguments: the committed 20 x 4 x 4 block in this
# directory. With ALONG ACROSS DIR: that block in DIR (80 12 gives 40,560 DOFs and
# 97 MB of matrices, 100 12 gives 50,700 DOFs and 121 MB: not committed). Needs python3
# and ccx (Debian calculix-ccx; bash scripts/system-deps.sh installs it). ccx also writes
# block.12d, .cvg, .dat, .frd, .sta, which are removed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
along="${1:-20}"
across="${2:-4}"
dir="${3:-$here}"
mkdir -p "$dir"
python3 "$here/make_deck.py" "$along" "$across" > "$dir/block.inp"
cd "$dir"
ccx -i block > /dev/null
rm -f block.12d block.cvg block.dat block.frd block.sta spooles.out
