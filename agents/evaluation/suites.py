"""The named runs of ``scripts/evaluate.py --suite``: which agents, scenarios, Δd and episode counts."""

from __future__ import annotations

#: Preset runs (``scripts/evaluate.py --suite``); the clairvoyant limit is added to every one.
SUITES = {
    "default": dict(  # oracle-static (blind to motion, slow) is in "large" only: make demo stays within 3 minutes
        agents="straight,velocity-obstacle,pso,abc,pso-predictive,abc-predictive,astar-spacetime,pso-spacetime,abc-spacetime,ppo",
        scenarios="random,paper-case-3",
        delta_d="0,0.1,0.25,0.5,1,2",
        episodes=50,
    ),
    # CrowdNav's protocol (Chen et al. 2019): its 500 test episodes per setting, humans at their own
    # 1 m/s (Δd = 1 m/s x 0.25 s / 0.3 m = 5/6), robot invisible and visible
    "crowdnav": dict(
        agents="straight,velocity-obstacle,orca,pso,abc,pso-predictive,abc-predictive,astar-spacetime,pso-spacetime,abc-spacetime,"
        "astar-crowd,pso-crowd,abc-crowd,ppo",
        scenarios="crowdnav-circle-crossing,crowdnav-square-crossing,crowdnav-circle-crossing-visible,crowdnav-square-crossing-visible",
        delta_d="0.8333333333333334",
        episodes=500,
    ),
    # walls and maps (issue 21): every family with bouncing obstacles and with ORCA humans
    "maps": dict(
        agents="straight,velocity-obstacle,orca,oracle-static,pso,abc,pso-predictive,abc-predictive,astar-spacetime,"
        "pso-spacetime,abc-spacetime,astar-crowd,pso-crowd,abc-crowd,ppo",
        scenarios="corridor,doorway,intersection,cluttered-room,maze,corridor-crowd,doorway-crowd,intersection-crowd,"
        "cluttered-room-crowd,maze-crowd",
        delta_d="0.25,0.5,1",
        episodes=200,
    ),
    # crowded and fast (issue 22): random scenes at 30 and 50 obstacles (a preset's own count, see
    # agents.evaluation.entrants), every space-time planner against the limit; astar-crowd is left
    # out: its cone of futures is for obstacles that steer, and these bounce as the physics predicts
    "dense": dict(
        agents="astar-spacetime,pso-spacetime,abc-spacetime",
        scenarios="random:n_obstacles=30,random:n_obstacles=50",
        delta_d="1,2,4",
        episodes=200,
    ),
    "large": dict(
        agents="straight,velocity-obstacle,oracle-static,pso,abc,pso-vanilla,abc-vanilla,pso-predictive,abc-predictive,"
        "astar-spacetime,pso-spacetime,abc-spacetime,ppo",
        scenarios="random,paper-case-1,paper-case-2,paper-case-3",
        delta_d="0,0.1,0.125,0.25,0.5,1,2",
        episodes=100,
    ),
}
