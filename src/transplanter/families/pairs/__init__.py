"""Gear-pair studies, a pair's journey in stations: pitch curves (:mod:`~.pitch`), the toothed pair
(:mod:`~.toothed`, ``ToothedPairStudy``) with its *size and cut* (:mod:`~.pair_cut`), *prove*
(:mod:`~.pair_proof`) and *make and assemble* (:mod:`~.pair_assembly`) stations, incomplete pairs
with dwells (:mod:`~.incomplete_pair`, ``IncompletePairStudy``) with their *prove*
(:mod:`~.incomplete_proof`, each position judged by its phase) and *make and assemble*
(:mod:`~.incomplete_assembly`) stations, and the one-call pair from a transmission ratio
(:mod:`~.gear_pair`, ``transplanter pair``).

May import
    :mod:`transplanter.families.builder` and the stations below the families.
"""
