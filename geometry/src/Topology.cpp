// TODO: implemented by the Topology work item
