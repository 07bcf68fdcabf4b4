class ParallelEnv: pass
