"""Grasp trials in MuJoCo: one trial's phases (``trial``), its control loop (``runner``), its
record (``result``) and scoring (``scoring``), a trial of a given grasp pose (``given_grasp``)
and the full observe -> detect -> plan -> execute chain (``chain``). ``trial_config``,
``chain_config`` and ``protocol`` import no MuJoCo."""
