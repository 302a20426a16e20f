import agents


def _v(name, **kw):
    def f(env, seed=None):
        return agents.make(name, env, seed=seed, **kw)
    return f


abc_nostall = _v("abc-spacetime", stall=0)
abc_penalty = _v("abc-spacetime", constraint="penalty")
abc_contacts = _v("abc-spacetime", violation="contacts", constraint="penalty", stall=0)  # the pre-issue-22 defaults
pso_contacts = _v("pso-spacetime", violation="contacts", constraint="penalty", stall=0)
