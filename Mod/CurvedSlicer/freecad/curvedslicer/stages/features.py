"""The result features a Job's stages keep in its groups ("Layers", "Paths", "Poses"): creating a
group, listing its members, and retiring the features a smaller result no longer uses. App side:
no GUI imports.

Removing document objects inside a recompute (``execute``) corrupts the document, so a stage run
by a recompute empties and hides surplus features (``LayerIndex`` 0) and they are removed
afterwards (``prune_unused_features``); a stage run outside a recompute (api.run) removes them at
once.
"""


def ensure_group(job, link, name, label):
    """The group the Job's property `link` (e.g. "LayersGroup") points to; created (named
    `name`, labelled "<Job label> <label>") and added to the Job when missing."""
    if getattr(job, link) is None:
        group = job.Document.addObject("App::DocumentObjectGroup", name)
        group.Label = "%s %s" % (job.Label, label)
        job.addObject(group)
        setattr(job, link, group)
    return getattr(job, link)


def group_members(group):
    """The objects of `group` (none when it is None). An undo or redo in progress can leave
    entries of a group's list empty (None); they are skipped."""
    if group is None:
        return []
    return [o for o in group.Group if o is not None]


def retire_features(group, features, prune, clear, label):
    """Features of a Job's group (Layers, Paths) that a smaller result no longer uses: removed when
    `prune` (only outside a recompute: removing objects inside execute() corrupts the document),
    else emptied by `clear(feature)`, marked LayerIndex 0, relabelled `label` and hidden (they are
    pruned after the recompute, see prune_unused_features)."""
    for feature in features:
        if prune:
            group.removeObject(feature)
            group.Document.removeObject(feature.Name)
        else:
            clear(feature)
            feature.LayerIndex = 0
            feature.Label = label
            feature.Visibility = False
            feature.purgeTouched()


def prune_unused_features(group):
    """Removes the features of a Job's group (Layers, Paths) that a smaller result emptied inside
    a recompute: those with LayerIndex 0. Call outside a recompute (removing objects inside
    execute() corrupts the document)."""
    for feature in [o for o in group_members(group) if "LayerIndex" in o.PropertiesList
                    and o.LayerIndex == 0]:
        group.removeObject(feature)
        group.Document.removeObject(feature.Name)
