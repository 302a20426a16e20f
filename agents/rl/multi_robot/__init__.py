"""One policy for every robot of the multi-robot env (parameter sharing), trained with SB3 through
PettingZoo's vector adapter (SuperSuit): ``agents.rl.multi_robot.shared_env`` (the robots' features and
actions, and the vector env), ``agents.rl.multi_robot.training`` (the run)."""
