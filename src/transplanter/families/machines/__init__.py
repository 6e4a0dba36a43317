"""Whole-machine studies: seed 004's differential planetary machine (:mod:`~.planetary_machine`,
posed from its pair's files in :mod:`~.planetary_posing`, judged in :mod:`~.planetary_judging`),
seed 002's double-carrier machine (:mod:`~.carrier_machine`, posed in :mod:`~.carrier_posing`,
judged in :mod:`~.carrier_judging`) with the parts it makes (:mod:`~.carrier_making`); what both
share: the planes their bodies sit in (:mod:`~.layers`), what they judge and record alike — a
tool's phases and work depth, the motion table and pictures (:mod:`~.judging`) — what every
machine study writes and reads (:mod:`~.record`), and what a shop assembles it from: the bill of
materials (:mod:`~.bill`), the bought parts its drawings name (:mod:`~.bought`), the assembly STEP,
the assembly drawing with balloons and its picture (:mod:`~.assembly`); and what it carries: the
masses from the assembly's bodies, the supports' lives and the shaking force (:mod:`~.loads`),
seed 004's loads model (:mod:`~.planetary_loads`).

May import
    the other family packages (builder, pairs, mechanisms) and the stations below the families.
"""
