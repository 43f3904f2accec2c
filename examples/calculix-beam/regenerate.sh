#!/usr/bin/env bash
# Regenerates the deck and CalculiX's matrices of the paper beam (beam.inp -> beam.sti,
# beam.mas, beam.dof) in this directory. Needs python3 and ccx (Debian calculix-ccx;
# bash scripts/system-deps.sh installs it). ccx also writes beam.12d, .cvg, .dat, .frd,
# .sta, which are removed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
python3 make_deck.py 100 1 > beam.inp
ccx -i beam > /dev/null
rm -f beam.12d beam.cvg beam.dat beam.frd beam.sta spooles.out
