"""The gymnasium env with the quadric detector as a scripted policy, a few episodes.

python examples/env_policy.py [EPISODES]
"""

import sys

import gymnasium

import simgrasp  # noqa: F401  (registers simgrasp/HandleGrasp-v0)
from simgrasp.envs.policy import DetectorPolicy

episodes = int(sys.argv[1]) if len(sys.argv) > 1 else 3

env = gymnasium.make("simgrasp/HandleGrasp-v0", objects=("gen_hammer", "gen_mug"))
policy = DetectorPolicy.for_env(env, "quadric")
obs, info = env.reset(seed=0)
for episode in range(episodes):
    action = policy.act(obs, seed=info["episode_seed"])
    obs, reward, terminated, truncated, info = env.step(action)
    outcome = info["failure"] or ("held by the handle" if info["on_handle"] else "held elsewhere")
    print(f"episode {episode}: {info['object']} reward {reward} ({outcome})")
    obs, info = env.reset()
env.close()
