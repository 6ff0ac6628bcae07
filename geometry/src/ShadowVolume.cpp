// TODO: implemented by the ShadowVolume work item
