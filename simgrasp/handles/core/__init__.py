"""The quadric handle detector: its settings (:mod:`.config`), its handle tests
(:mod:`.criteria`, :mod:`.plate`), its passes and clustering (:mod:`.quadric_passes`,
:mod:`.cluster`) and what every detector returns (:mod:`.detection`)."""
