"""Grasp trials in MuJoCo: one trial (``trial``) runs the phases (``phases``: settle, approach,
close, lift, hold, tugs, shake) of a protocol (``protocol``: the registry of named phase
sequences and their settings) on a shared state (``state``) through its control loop
(``runner``); its record (``result``) and scoring (``scoring``), a trial of a given grasp pose
(``given_grasp``) and the full observe -> detect -> plan -> execute chain (``chain``).
``trial_config``, ``shake``, ``chain_config`` and ``protocol`` import no MuJoCo."""
