// TODO: implemented by the Sampling work item
