"""Handle detectors the quadric detector is compared with: ten Pas & Platt's cylindrical shells
(:mod:`.tenpas_detector`, its settings :mod:`.tenpas_config`), the proposer ``tenpas``."""
