"""The device learns its own offset-vs-temperature table in the field.

The learner (csrc/learn/, sig_learn.h) sums still samples per temperature
bin in fixed point, fits a table when enough bins are covered, validates it
on bins it was not fitted on against the model in use, and commits it into
the A/B coefficient image only when it is better by a margin; a CUSUM on
the still residual flags a stale model.

=======================  ==============================================
name                     what it is
=======================  ==============================================
``LearnConfig``          sig_learn_config; ``for_range`` picks the bins
``replay``               a field log through the device loop (C)
``ReplayResult``         what the device did: corrected readings, flags,
                         model sequence, commits, last image
``DeviceLearner``        the C learner and its model, one call at a time
``STATE_BYTES``          sizeof(sig_learn) on this host
``write_outputs``        replay.csv, model.bin, commits.json, plot
=======================  ==============================================
"""
from ._config import LearnConfig
from ._learn import STATE_BYTES, DeviceLearner
from ._replay import ReplayResult, replay
from ._outputs import write_outputs

__all__ = ["LearnConfig", "replay", "ReplayResult", "DeviceLearner", "STATE_BYTES", "write_outputs"]
